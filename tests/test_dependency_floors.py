"""The lowest-versions stage (.ci/lowest.sh) installs exactly the floors pyproject.toml
declares: .ci/lowest-constraints.txt pins every direct dependency (core, and the test
and plot extras) at its ``>=`` floor and nothing else, so the two cannot drift apart.
Reads pyproject.toml with tomllib where there is one (Python >= 3.11), else with the
small reader below (no dependency)."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXTRAS = ("test", "plot")         # the extras the stage installs: pip install ".[test,plot]"


def _arrays(text):
    """``{section: {key: [strings]}}`` for the string arrays and strings of a TOML file
    written like pyproject.toml (one ``key = value`` per entry, arrays may span lines)."""
    found, section = {}, ""
    entry = r'^([A-Za-z0-9_.-]+)\s*=\s*(\[(?:"[^"]*"|[^]"])*\]|"[^"]*")'
    for match in re.finditer(r'^\[([^]]+)\]\s*$|' + entry, text, re.MULTILINE):
        if match.group(1):
            section = match.group(1).strip()
        else:
            value = re.findall(r'"([^"]*)"', match.group(3))
            found.setdefault(section, {})[match.group(2)] = (
                value if match.group(3).startswith("[") else value[0])
    return found


def _project(text):
    try:
        import tomllib
    except ImportError:                 # Python 3.10
        tables = _arrays(text)
        return {"requires-python": tables["project"]["requires-python"],
                "dependencies": tables["project"]["dependencies"],
                "optional-dependencies": tables["project.optional-dependencies"]}
    return tomllib.loads(text)["project"]


def _name(requirement):
    return re.match(r"[A-Za-z0-9_.-]+", requirement).group(0).lower().replace("_", "-")


def declared_floors():
    project = _project((ROOT / "pyproject.toml").read_text())
    requirements = list(project["dependencies"])
    for extra in EXTRAS:
        requirements += project["optional-dependencies"][extra]
    floors = {}
    for requirement in requirements:
        floor = re.search(r">=\s*([0-9][0-9A-Za-z.]*)", requirement)
        assert floor, f"{requirement!r} in pyproject.toml declares no floor (>=)"
        assert floors.get(_name(requirement), floor.group(1)) == floor.group(1), requirement
        floors[_name(requirement)] = floor.group(1)
    return floors


def pinned():
    pins = {}
    for line in (ROOT / ".ci" / "lowest-constraints.txt").read_text().splitlines():
        line = line.split("#")[0].strip()
        if line:
            match = re.fullmatch(r"([A-Za-z0-9_.-]+)==([0-9][0-9A-Za-z.]*)", line)
            assert match, f"{line!r}: the constraints file pins exact versions only"
            assert _name(match.group(1)) not in pins, f"{line!r} pinned twice"
            pins[_name(match.group(1))] = match.group(2)
    return pins


def test_the_constraints_pin_exactly_the_declared_floors():
    assert pinned() == declared_floors()


def test_the_stage_runs_the_lowest_declared_python():
    project = _project((ROOT / "pyproject.toml").read_text())
    lowest = re.fullmatch(r">=\s*(3\.\d+)", project["requires-python"]).group(1)
    script = (ROOT / ".ci" / "lowest.sh").read_text()
    assert f"python{lowest} " in script and f"!= ({lowest.replace('.', ', ')})" in script


def test_the_small_reader_reads_pyproject_as_tomllib_does():
    text = (ROOT / "pyproject.toml").read_text()
    try:
        import tomllib
    except ImportError:                 # Python 3.10: only the small reader exists
        return
    project, tables = tomllib.loads(text)["project"], _arrays(text)
    assert tables["project"]["dependencies"] == project["dependencies"]
    assert tables["project"]["requires-python"] == project["requires-python"]
    assert tables["project.optional-dependencies"] == project["optional-dependencies"]
