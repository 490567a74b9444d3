"""The pytest plugin of benchmarks/mutation.py (``-p mutation_probe``, from a copy of the
repository where this file sits at the top), and the hook its test map installs in
processes the tests start (the copy's ``sitecustomize.py`` calls :func:`child`).

Map mode (``MECHDYN_MUTATION_MAP`` = a folder): records the order of the collected tests,
per test its duration, outcome and the mechdyn code objects it called (``sys.setprofile``, call events only), the functions
called while one of mechdyn's modules is imported, and per test file the seconds its
collection took, and writes them to ``<folder>/part-<pid>.json`` (one
a process: pytest-xdist's workers each write theirs); a process a test starts (its node id in
``MECHDYN_MUTATION_TEST``) writes ``<folder>/child-<pid>.json`` at exit.
Mutant mode (``MECHDYN_MUTATION_ORDER`` = a file of node ids): runs the tests in that
order, after checking that mechdyn is imported from the copy (``MECHDYN_MUTATION_SLOT``):
a mutant tested against the unmutated package would pass as a survivor. Once the tests have
run ``MECHDYN_MUTATION_CAP`` seconds, no further test starts: the run exits with status
6 (``mutation cap``), the mutant counted as not killed.
"""
import json
import os
import sys
import threading
import time
from pathlib import Path

import pytest

MAP, TEST = "MECHDYN_MUTATION_MAP", "MECHDYN_MUTATION_TEST"
ORDER, SLOT, CAP = "MECHDYN_MUTATION_ORDER", "MECHDYN_MUTATION_SLOT", "MECHDYN_MUTATION_CAP"
CAPPED = 6                                      # the exit status of a run stopped at the cap
ROOT = Path(__file__).resolve().parent          # the copy: mechdyn/ and tests/ are here


class Calls:
    """A profile function that keeps (file, first line) of every code object of mechdyn/
    that is called; C calls and returns cost one comparison. numba's dispatcher reports a
    call of a compiled function from Python to a profile function as a call of its Python
    code (not calls from compiled code to compiled code). The map's run takes about twice
    as long as without; a global trace function (``sys.settrace``), which sees no C calls,
    was 20 % faster but does not see the compiled functions called from Python."""

    def __init__(self):
        self.prefix = str(ROOT / "mechdyn") + os.sep
        self.seen, self.at_import, self.importing = set(), set(), 0

    def __call__(self, frame, event, arg):
        if event == "call":
            code = frame.f_code
            if code.co_filename.startswith(self.prefix):
                self.seen.add((code.co_filename, code.co_firstlineno))
                if self.importing:
                    self.at_import.add((code.co_filename, code.co_firstlineno))
                if code.co_name == "<module>":
                    self.importing += 1
        elif event == "return" and self.importing and frame.f_code.co_name == "<module>" \
                and frame.f_code.co_filename.startswith(self.prefix):
            self.importing -= 1

    def start(self):
        sys.setprofile(self)
        threading.setprofile(self)

    def take(self) -> dict:
        """The calls since the last take: {file relative to ROOT: [first lines]}."""
        seen, self.seen = self.seen, set()
        return _relative(seen)


def _relative(calls) -> dict:
    found, skip = {}, len(str(ROOT)) + 1
    for name, line in sorted(calls):
        found.setdefault(name[skip:], []).append(line)
    return found


def _write(name, data):
    folder = Path(os.environ[MAP])
    (folder / f"{name}-{os.getpid()}.json").write_text(json.dumps(data))


def child():
    """In a process a test started, while the map is built: record its calls for that test."""
    if os.environ.get(MAP) and os.environ.get(TEST):
        calls = Calls()
        calls.start()
        import atexit
        atexit.register(lambda: _write("child", {"test": os.environ[TEST], "calls": calls.take(),
                                                 "at_import": _relative(calls.at_import)}))


class Recorder:
    """Map mode: per test, the duration of its setup, call and teardown, whether all of
    them passed, and the calls."""

    def __init__(self):
        self.calls, self.tests, self.collect, self.order = Calls(), {}, {}, []

    def pytest_sessionstart(self):
        self.calls.start()

    @pytest.hookimpl(hookwrapper=True)
    def pytest_make_collect_report(self, collector):
        start = time.perf_counter()
        yield
        if isinstance(collector, pytest.Module):
            name = str(Path(collector.path).relative_to(ROOT))
            self.collect[name] = round(time.perf_counter() - start, 3)

    def pytest_collection_finish(self, session):
        self.order = [item.nodeid for item in session.items]    # the suite's own order

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_protocol(self, item):
        os.environ[TEST] = item.nodeid
        self.calls.take()                    # drop what ran outside tests (collection)
        start = time.perf_counter()
        yield
        self.tests.setdefault(item.nodeid, {"outcome": "passed"}).update(
            seconds=round(time.perf_counter() - start, 3), calls=self.calls.take())
        os.environ.pop(TEST, None)

    def pytest_runtest_logreport(self, report):
        test = self.tests.setdefault(report.nodeid, {"outcome": "passed"})
        if report.failed or report.skipped and test["outcome"] == "passed":
            test["outcome"] = report.outcome

    def pytest_sessionfinish(self):
        sys.setprofile(None)
        _write("part", {"tests": self.tests, "collect": self.collect, "order": self.order,
                        "at_import": _relative(self.calls.at_import)})


class Ordered:
    """Mutant mode: the given tests, in the given order, against the copy's mechdyn,
    stopping after ``cap`` seconds of them."""

    def __init__(self, order, cap=float("inf")):
        self.order = {nodeid: i for i, nodeid in enumerate(order)}
        self.cap, self.spent, self.ran = cap, 0.0, 0

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_protocol(self, item, nextitem):
        start = time.perf_counter()
        yield
        self.spent += time.perf_counter() - start
        self.ran += 1
        if nextitem is not None and self.spent > self.cap and not item.session.testsfailed:
            pytest.exit(f"mutation cap: {self.ran} tests passed in {self.spent:.0f} s, "
                        "the rest not run", returncode=CAPPED)

    def pytest_collection_modifyitems(self, items):
        items.sort(key=lambda item: self.order.get(item.nodeid, len(self.order)))

    def pytest_collection_finish(self, session):
        """The test modules have imported mechdyn by now (unless the mutant broke it)."""
        mechdyn = sys.modules.get("mechdyn")
        slot = Path(os.environ[SLOT]).resolve()
        if mechdyn and slot not in Path(mechdyn.__file__).resolve().parents:
            pytest.exit(f"mechdyn imported from {mechdyn.__file__}, not {slot}", returncode=4)


def pytest_configure(config):
    if os.environ.get(MAP):
        config.pluginmanager.register(Recorder(), "mutation-map")
    elif os.environ.get(ORDER):
        order = Path(os.environ[ORDER]).read_text().split("\n")
        cap = float(os.environ.get(CAP, "inf"))
        config.pluginmanager.register(Ordered(order, cap), "mutation-order")
