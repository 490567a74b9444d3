"""The README's python blocks run as written, each on its own, in an empty folder (the
bundled models ship with the package; what the blocks write lands there)."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BLOCKS = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
HEAVY = ("periodic_steady_state", "md.sweep(")       # seconds each: run as slow tests
SHOWN = re.compile(r"^(?P<code>[^#=\n]+?)\s+# (?P<shown>\[.*?\])(;|$)")   # a shown list


def _cases():
    for index, block in enumerate(BLOCKS):
        heading = block.strip().splitlines()[0][:40]
        marks = [pytest.mark.slow] if any(word in block for word in HEAVY) else []
        yield pytest.param(block, id=f"{index}:{heading}", marks=marks)


def test_there_are_blocks():
    assert len(BLOCKS) >= 8


@pytest.mark.parametrize("block", list(_cases()))
def test_a_readme_block_runs_as_written(block, tmp_path, monkeypatch):
    """... and, doctest-style, a line ``expression  # [shown]`` prints as shown."""
    pytest.importorskip("matplotlib")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "readme"}
    exec(compile(block, "README.md", "exec"), namespace)
    for line in block.splitlines():
        match = SHOWN.match(line)
        if match:
            assert repr(eval(match["code"], namespace)) == match["shown"], line


def test_the_readme_shows_what_python_prints_of_three_results():
    shown = [line for block in BLOCKS for line in block.splitlines() if SHOWN.match(line)]
    assert len(shown) >= 3



def test_ci_runs_the_readmes_install_and_test_command():
    # .ci/run must install the project the README's way and run the README's test
    # command: both are read off the README's first screen, so they cannot drift apart.
    first_block = re.search(r"```bash\n(.*?)```", (ROOT / "README.md").read_text(), re.S)[1]
    test_line = next(line for line in first_block.splitlines() if "pytest" in line)
    install, command = (part.split("#")[0].strip() for part in test_line.split("&&"))
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    assert install in ci and command in ci
    assert ci.index(install) < ci.index(command)
