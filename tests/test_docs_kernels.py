"""The python blocks of docs/kernels.md run as written (they moved there from the
README, whose blocks and the guide's tests/test_docs_examples.py runs)."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BLOCKS = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "kernels.md").read_text(), re.S)


def test_there_is_a_block():
    assert BLOCKS


@pytest.mark.parametrize("block", BLOCKS)
def test_a_kernels_block_runs_as_written(block):
    pytest.importorskip("numba")
    exec(compile(block, "docs/kernels.md", "exec"), {"__name__": "kernels_doc"})
