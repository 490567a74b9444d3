"""One-off: move the flat mechdyn/ into stage subpackages and rewrite imports."""
import re, subprocess, pathlib
ROOT = pathlib.Path('/work/main')
STAGES = {
 'declare': 'elements couplings unilateral motors tables gear_loss scene scene_units dimensions parameters parameter_rules mechanism model_file',
 'derive': 'derive:lagrange latex reduction analytic linear modal transmission',
 'compile': 'codegen generate output_code loop_code linkage_code generated compile:compiler numba_model loop_numeric',
 'simulate': 'stepping events trajectory segments driver methods friction constrained contacts assembly loop_watch run_checks compiled_stepping mode_outputs result simulate:simulation',
 'analyse': 'periodic fluctuation sweeps sweep_file cycle cycle_result precision characteristics balancing joint_reactions link_motion linkage linkage_limits linkage_drive linkage_plots',
 'report': 'report:document animation',
 'cli': 'cli:main cli_linkage:linkage warm',
}
NEW = {}
for stage, names in STAGES.items():
    for item in names.split():
        old, _, new = item.partition(':')
        NEW[old] = f'{stage}.{new or old}'
# 1. move
for stage in STAGES:
    (ROOT/'mechdyn'/stage).mkdir(exist_ok=True)
for old, new in NEW.items():
    src = ROOT/'mechdyn'/f'{old}.py'; dst = ROOT/'mechdyn'/(new.replace('.', '/') + '.py')
    subprocess.run(['git', 'mv', str(src), str(dst)], cwd=ROOT, check=True)
# 2. rewrite relative imports inside mechdyn (not kernels)
def absolute(mod):
    return 'mechdyn.' + NEW.get(mod, mod)
rel_from = re.compile(r'^(\s*)from \.([A-Za-z_]\w*)((?:\.\w+)*) import ', re.M)
rel_bare = re.compile(r'^(\s*)from \. import ([^\n(]+)$', re.M)
for path in (ROOT/'mechdyn').rglob('*.py'):
    if 'kernels' in path.parts: continue
    text = path.read_text()
    text = rel_from.sub(lambda m: f'{m.group(1)}from {absolute(m.group(2))}{m.group(3)} import ', text)
    def bare(m):
        names = [n.strip() for n in m.group(2).split(',')]
        out = []
        for n in names:
            target = absolute(n.split(' as ')[0].strip())
            pkg, _, leaf = target.rpartition('.')
            alias = n.split(' as ')[1] if ' as ' in n else None
            out.append(f'{m.group(1)}from {pkg} import {leaf}' + (f' as {alias}' if alias and alias != leaf else ''))
        return '\n'.join(out)
    text = rel_bare.sub(bare, text)
    path.write_text(text)
# 3. text references everywhere
names = sorted(NEW, key=len, reverse=True)
dotted = re.compile(r'\bmechdyn\.(' + '|'.join(names) + r')\b(?!\.py)')
slashed = re.compile(r'\bmechdyn/(' + '|'.join(names) + r')\.py\b')
files = [p for p in ROOT.rglob('*') if p.is_file() and p.suffix in {'.py', '.md', '.toml', '.cfg', '.txt', '.ini', '.yml', '.yaml'} or p.name == 'run']
for path in files:
    if '.git' in path.parts or '.tmp_restructure' in path.parts or 'mutants' in path.parts: continue
    try: text = path.read_text()
    except Exception: continue
    new = dotted.sub(lambda m: 'mechdyn.' + NEW[m.group(1)], text)
    new = slashed.sub(lambda m: 'mechdyn/' + NEW[m.group(1)].replace('.', '/') + '.py', new)
    if new != text: path.write_text(new)
import json; json.dump(NEW, open(ROOT/'.tmp_restructure/map.json', 'w'), indent=1)
