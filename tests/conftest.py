"""Test session setup: a compile cache of the tests' own (subprocesses inherit it), so
tests neither read nor fill the user's ~/.cache/mechdyn: ``~/.cache/mechdyn-tests``,
kept between sessions (entries are keyed by the generator's source and authenticated,
so a changed mechdyn never meets a stale entry; numba compiles each scene's modules
once, not once per session), or a fresh folder of the session's own with
``MECHDYN_TEST_CACHE=fresh`` (a cold run), or the folder ``MECHDYN_TESTS_CACHE_FOLDER``
names (benchmarks/mutation.py: a fresh one per mutant). ``MECHDYN_CACHE=off`` is kept: no
disk cache at all. Registers the hypothesis profile ``mutation``
(no shrinking, no example database; derandomized, so a mutant's outcome reproduces, and no
deadline, so a mutant that only runs slower on a busy machine is not killed) for
benchmarks/mutation.py, ``ci`` (the default:
derandomized, so a failure reproduces; no deadline) and ``deep`` (2000 examples of the
differential tests, tests/test_differential.py: ``--hypothesis-profile=deep``)."""
import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import Phase, settings

_CHOSEN = "MECHDYN_TESTS_CACHE_FOLDER"      # inherited by the workers of `pytest -n`


def _tests_cache() -> str:
    chosen = os.environ.get(_CHOSEN)
    if chosen:                     # a pytest-xdist worker: the folder its controller chose
        return chosen
    if os.environ.get("MECHDYN_TEST_CACHE", "").lower() == "fresh":
        return tempfile.mkdtemp(prefix="mechdyn-test-cache-")
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    folder = base / "mechdyn-tests"
    folder.mkdir(mode=0o700, parents=True, exist_ok=True)
    return str(folder)


if os.environ.get("MECHDYN_CACHE", "").lower() != "off":
    os.environ["MECHDYN_CACHE"] = os.environ[_CHOSEN] = _tests_cache()

settings.register_profile("mutation", database=None, derandomize=True, deadline=None,
                          phases=[Phase.explicit, Phase.reuse, Phase.generate])
_NO_EXPLAIN = [Phase.explicit, Phase.reuse, Phase.generate, Phase.shrink]   # minutes each
settings.register_profile("ci", derandomize=True, deadline=None, phases=_NO_EXPLAIN)
settings.register_profile("deep", max_examples=2000, deadline=None, phases=_NO_EXPLAIN)
settings.load_profile("ci")


@pytest.fixture
def share_kernels():
    """``share(folder)``: make ``folder`` a cache folder (for a process the test starts)
    whose ``kernels/`` is this session's: numba's files of mechdyn's kernels do not
    depend on what else the cache holds, and sharing them spares each such process a
    cold compilation of the kernels (20-50 s); the scenes' entries stay the folder's own."""
    def share(folder):
        folder = Path(folder)
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        if os.environ.get(_CHOSEN):
            session = Path(os.environ[_CHOSEN]) / "kernels"
            session.mkdir(mode=0o700, parents=True, exist_ok=True)
            (folder / "kernels").symlink_to(session, target_is_directory=True)
        return folder
    return share
