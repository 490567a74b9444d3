"""split.py SRC NEWMOD 'docstring' name1 name2 ...  — move top-level defs to a sibling module."""
import ast, re, subprocess, sys, pathlib
src = pathlib.Path(sys.argv[1]).resolve(); newname = sys.argv[2]; doc = sys.argv[3]; names = set(sys.argv[4:])
text = src.read_text(); lines = text.splitlines(keepends=True)
tree = ast.parse(text)
imports = [n for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom))]
header = ''.join(''.join(lines[n.lineno-1:n.end_lineno]) for n in imports if not (isinstance(n, ast.ImportFrom) and n.module == '__future__'))
moved, keep_ranges = [], []
body = tree.body
for i, node in enumerate(body):
    name = getattr(node, 'name', None)
    if name is None and isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name):
        name = node.targets[0].id
    if name in names:
        start = (node.decorator_list[0].lineno if getattr(node, 'decorator_list', None) else node.lineno)
        # include comment lines directly above
        while start > 1 and lines[start-2].lstrip().startswith('#'):
            start -= 1
        moved.append((start, node.end_lineno))
found = set()
for node in body:
    n = getattr(node, 'name', None) or (node.targets[0].id if isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name) else None)
    if n in names: found.add(n)
missing = names - found
assert not missing, missing
chunks = [''.join(lines[a-1:b]) for a, b in moved]
drop = set()
for a, b in moved: drop.update(range(a, b+1))
rest = ''.join(l for k, l in enumerate(lines, 1) if k not in drop)
rest = re.sub(r'\n{3,}', '\n\n\n', rest)
pkg = '.'.join(src.with_suffix('').parts[src.with_suffix('').parts.index('mechdyn'):-1])
base_mod = f'{pkg}.{src.stem}'
# what the new module needs from the old: every top-level name of the rest
rest_tree = ast.parse(rest)
rest_names = set(); SKIP = {'__all__'}
for node in rest_tree.body:
    if isinstance(node, (ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef)): rest_names.add(node.name)
    elif isinstance(node, ast.Assign):
        for tg in node.targets:
            if isinstance(tg, ast.Name) and tg.id not in SKIP: rest_names.add(tg.id)
new_text = f'"""{doc}\n"""\nfrom __future__ import annotations\n\n' + header + f'from {base_mod} import ({", ".join(sorted(rest_names))})\n\n\n' + '\n\n'.join(c.rstrip('\n') + '\n' for c in chunks)
newpath = src.with_name(newname + '.py')
newpath.write_text(new_text)
# fix __all__ of rest: remove moved names
m = re.search(r'__all__ = \[(.*?)\]', rest, re.S)
if m:
    items = [x.strip() for x in m.group(1).split(',') if x.strip()]
    kept = [x for x in items if x.strip('"\'') not in names]
    movedall = [x for x in items if x.strip('"\'') in names]
    rest = rest.replace(m.group(0), '__all__ = [' + ', '.join(kept) + ']')
    new_text = newpath.read_text().replace('from __future__ import annotations\n', 'from __future__ import annotations\n', 1)
    new_text = new_text.replace('\n\n\n', f'\n\n__all__ = [{", ".join(movedall)}]\n\n\n', 1) if movedall else new_text
    # put __all__ after imports: simple approach: append after the import of base module
    newpath.write_text(new_text)
src.write_text(rest)
subprocess.run(['autoflake', '--in-place', '--remove-all-unused-imports', str(src), str(newpath)])
print('moved', sorted(found), 'to', newpath)
