"""The pytest plugin of benchmarks/mutation.py (``-p mutation_probe``, from a copy of the
repository where this file sits at the top), and the hook its test map installs in
processes the tests start (the copy's ``sitecustomize.py`` calls :func:`child`).

Map mode (``MECHDYN_MUTATION_MAP`` = a folder): records the order of the collected tests,
per test its duration, outcome and the lines of mechdyn it ran (coverage.py, one dynamic
context a test), the lines run outside any test (while modules are imported, at
collection), and per test file the seconds its collection took, and writes them to
``<folder>/part-<pid>.json`` (one a process: pytest-xdist's workers each write theirs); a
process a test starts (its node id in ``MECHDYN_MUTATION_TEST``) writes
``<folder>/child-<pid>.json`` at exit.

Mutant mode (:class:`Ordered`, registered by benchmarks/mutation_server.py): runs the
given tests in the given order; once they have run ``cap`` seconds, no further test starts:
the run exits with status 6 (``mutation cap``), the mutant counted as not killed.
"""
import json
import os
import time
from pathlib import Path

import pytest

MAP, TEST = "MECHDYN_MUTATION_MAP", "MECHDYN_MUTATION_TEST"
CAPPED = 6                                      # the exit status of a run stopped at the cap
ROOT = Path(__file__).resolve().parent          # the copy: mechdyn/ and tests/ are here
OUTSIDE = ""                                    # the context of lines run outside any test


class Lines:
    """coverage.py measuring mechdyn's lines, one dynamic context a test (its node id).
    Lines of numba-compiled functions run as machine code and are not seen (numba reports
    the lines it compiles to coverage, in the context of whatever compiled them; the
    harness judges compiled code by other rules and ignores them)."""

    def __init__(self, context=OUTSIDE):
        import coverage
        self.coverage = coverage.Coverage(data_file=None, config_file=False, branch=False,
                                          include=[str(ROOT / "mechdyn" / "*")])
        self.coverage.start()
        self.coverage.switch_context(context)

    def switch(self, context):
        self.coverage.switch_context(context)

    def take(self) -> dict:
        """{file relative to ROOT: {line: [contexts]}}, measuring stopped."""
        self.coverage.stop()
        data, skip, found = self.coverage.get_data(), len(str(ROOT)) + 1, {}
        for name in data.measured_files():
            lines = data.contexts_by_lineno(name)
            if lines:
                found[name[skip:]] = {str(k): sorted(v) for k, v in lines.items()}
        return found


def _write(name, data):
    folder = Path(os.environ[MAP])
    (folder / f"{name}-{os.getpid()}.json").write_text(json.dumps(data))


def child():
    """In a process a test started, while the map is built: record its lines for that test."""
    if os.environ.get(MAP) and os.environ.get(TEST):
        lines = Lines(os.environ[TEST])
        import atexit
        atexit.register(lambda: _write("child", {"lines": lines.take()}))


class Recorder:
    """Map mode: per test, the duration of its setup, call and teardown, whether all of
    them passed, and the lines it ran."""

    def __init__(self):
        self.lines, self.tests, self.collect, self.order = Lines(), {}, {}, []

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
        self.lines.switch(item.nodeid)
        start = time.perf_counter()
        yield
        self.tests.setdefault(item.nodeid, {"outcome": "passed"})["seconds"] = round(
            time.perf_counter() - start, 3)
        self.lines.switch(OUTSIDE)
        os.environ.pop(TEST, None)

    def pytest_runtest_logreport(self, report):
        test = self.tests.setdefault(report.nodeid, {"outcome": "passed"})
        if report.failed or report.skipped and test["outcome"] == "passed":
            test["outcome"] = report.outcome

    def pytest_sessionfinish(self):
        _write("part", {"tests": self.tests, "collect": self.collect, "order": self.order,
                        "lines": self.lines.take()})


class Ordered:
    """Mutant mode: the given tests, in the given order, stopping after ``cap`` seconds
    of them."""

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


def pytest_configure(config):
    if os.environ.get(MAP):
        config.pluginmanager.register(Recorder(), "mutation-map")
