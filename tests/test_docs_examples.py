"""Every python block of README.md and of the user guide (docs/guide/*.md) runs as
written, each on its own, in an empty folder (the bundled models ship with the package;
what the blocks write lands there); doctest-style, a line ``expression  # [shown]`` must
print as shown. Blocks of seconds each (periodic steady states, sweeps) are slow tests."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]
HEAVY = ("periodic_steady_state", "md.sweep(")       # seconds each: run as slow tests
SHOWN = re.compile(r"^(?P<code>[^#=\n]+?)\s+# (?P<shown>\[.*?\])(;|$)")   # a shown list


def blocks(path):
    return re.findall(r"```python\n(.*?)```", path.read_text(), re.S)


def _cases():
    for page in PAGES:
        name = page.relative_to(ROOT).as_posix()
        for index, block in enumerate(blocks(page)):
            heading = block.strip().splitlines()[0][:40]
            marks = [pytest.mark.slow] if any(word in block for word in HEAVY) else []
            yield pytest.param(name, block, id=f"{name}:{index}:{heading}", marks=marks)


CASES = list(_cases())


def test_the_pages_hold_the_blocks_the_readme_held():
    # README.md held 18 python blocks before the guide took them over; the front door
    # keeps one, the guide the rest.
    assert len(blocks(ROOT / "README.md")) == 1
    assert len(CASES) >= 19


@pytest.mark.parametrize("page, block", CASES)
def test_a_block_runs_as_written(page, block, tmp_path, monkeypatch):
    """... and, doctest-style, a line ``expression  # [shown]`` prints as shown."""
    pytest.importorskip("matplotlib")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "docs_example"}
    exec(compile(block, page, "exec"), namespace)
    for line in block.splitlines():
        match = SHOWN.match(line)
        if match:
            assert repr(eval(match["code"], namespace)) == match["shown"], line


def test_the_pages_show_what_python_prints_of_four_results():
    shown = [line for _, block in (case.values for case in CASES)
             for line in block.splitlines() if SHOWN.match(line)]
    assert len(shown) >= 4
