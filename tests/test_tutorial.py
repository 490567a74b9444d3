"""The tutorial's code blocks run, from the repository root, and show what they say."""
import doctest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_tutorial_runs(monkeypatch):
    monkeypatch.chdir(ROOT)
    outcome = doctest.testfile(str(ROOT / "docs" / "tutorial.md"), module_relative=False,
                               optionflags=doctest.ELLIPSIS, verbose=False)
    assert outcome.attempted > 20
    assert outcome.failed == 0
