"""The package reads as its pipeline: every import inside ``mechdyn`` (at module level or
inside a function) points to the shared base, to its own stage or to an earlier one, no
module imports itself through others (no circles, inside a stage either), and no module
is over about 400 lines."""
import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "mechdyn"
# The order of the stages; the shared base (top-level modules and the kernels) comes first
# and the package's own __init__ (the public names) last.
STAGES = ["base", "declare", "derive", "compile", "simulate", "analyse", "report", "cli",
          "facade"]
FACADE_MODULES = {"__init__", "machine"}
MAX_LINES = 420


def stage_of(module: str) -> str:
    """The stage of a dotted module name inside mechdyn ('mechdyn.derive.latex')."""
    parts = module.split(".")[1:]
    if not parts:
        return "facade"
    if parts[0] in STAGES:
        return parts[0]
    if len(parts) == 1 and parts[0] in FACADE_MODULES:
        return "facade"
    return "base"


def module_name(path: Path) -> str:
    relative = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(relative.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def is_module(dotted: str) -> bool:
    path = PACKAGE.parent.joinpath(*dotted.split("."))
    return path.with_suffix(".py").exists() or (path / "__init__.py").exists()


def imports_of(path: Path):
    """(line, imported module) for every import of a mechdyn module in the file."""
    own = module_name(path)
    package = own if path.name == "__init__.py" else own.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            modules = [f"{target}.{alias.name}" for alias in node.names
                       if is_module(f"{target}.{alias.name}")]
            if target.startswith("mechdyn"):
                # ``from mechdyn.x import y`` imports module mechdyn.x.y if there is one
                for name in modules if len(modules) == len(node.names) else [target]:
                    yield node.lineno, name
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("mechdyn"):
                    yield node.lineno, alias.name


SOURCES = sorted(PACKAGE.rglob("*.py"))


def test_the_stages_are_the_subpackages():
    assert {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists()} == \
        set(STAGES[1:-1]) | {"kernels"}


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_point_only_to_the_base_the_same_stage_or_earlier(path):
    own = STAGES.index(stage_of(module_name(path)))
    backward = [f"line {line}: {target} ({stage_of(target)})"
                for line, target in imports_of(path)
                if STAGES.index(stage_of(target)) > own]
    assert not backward, f"{path.relative_to(PACKAGE)} imports later stages: {backward}"


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_module_is_over_about_400_lines(path):
    assert len(path.read_text().splitlines()) <= MAX_LINES


def test_the_test_sees_a_backward_import(tmp_path):
    """The checker itself: an earlier stage importing a later one is caught."""
    fake = PACKAGE / "declare" / "elements.py"
    lines = list(imports_of(fake))
    assert all(STAGES.index(stage_of(t)) <= STAGES.index("declare") for _, t in lines)
    assert stage_of("mechdyn.report.document") == "report"
    assert stage_of("mechdyn.errors") == "base" and stage_of("mechdyn") == "facade"


def import_graph(sources=SOURCES) -> dict:
    """Module -> the mechdyn modules it imports (anywhere in the file)."""
    graph = {}
    for path in sources:
        own = module_name(path)
        graph[own] = {target for _, target in imports_of(path) if target != own}
    return graph


def circles(graph) -> list:
    """The import circles of ``graph``: its strongly connected components of more than
    one module (Tarjan's algorithm, iterative), each sorted."""
    index, low, on_stack, stack, found = {}, {}, set(), [], []
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph.get(root, ()))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, targets = work[-1]
            target = next(targets, None)
            if target is not None:
                if target not in index:
                    index[target] = low[target] = len(index)
                    stack.append(target)
                    on_stack.add(target)
                    work.append((target, iter(sorted(graph.get(target, ())))))
                elif target in on_stack:
                    low[node] = min(low[node], index[target])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def test_no_import_circles():
    """No module imports itself through others, inside a stage or across stages."""
    graph = import_graph()
    found = [[f"{a} -> {b}" for a in circle for b in sorted(graph[a]) if b in circle]
             for circle in circles(graph)]
    assert not found, f"import circles: {found}"


def test_the_test_sees_a_circle():
    """The checker itself: a circle of three modules (and one of two inside it) is
    found, a chain into it is not part of it, and a graph without one is clean."""
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": set(), "e": {"a"}}
    assert circles(graph) == [["a", "b", "c"]]
    assert circles({"x": {"y"}, "y": {"x"}, "z": set()}) == [["x", "y"]]
    assert circles({"x": {"y"}, "y": {"z"}, "z": set()}) == []
    real = import_graph()
    real["mechdyn.errors"] = real["mechdyn.errors"] | {"mechdyn.declare.elements"}
    assert any({"mechdyn.errors", "mechdyn.declare.elements"} <= set(c)
               for c in circles(real))
