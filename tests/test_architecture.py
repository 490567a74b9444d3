"""The package reads as its pipeline: every import inside ``mechdyn`` (at module level or
inside a function) points to the shared base, to its own stage or to an earlier one, and
no module is over about 400 lines."""
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
