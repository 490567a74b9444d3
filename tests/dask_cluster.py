"""A Dask cluster of real processes for the tests, as users start one: ``dask scheduler``
and ``dask worker`` processes (each with its nanny, one thread) on 127.0.0.1, on random
free ports.

Every process runs in a process group of its own and is ended with it (SIGTERM, then
SIGKILL) when the cluster closes, also when a test fails. Their lifetime is bounded if
the test process itself is killed: the scheduler ends after ``IDLE`` seconds without
work, and a worker whose scheduler is gone ends after ``DEATH`` seconds. Only one such
cluster runs at a time on the machine (a file lock: pytest-xdist may run the tests of
one module in two processes). The workers import what the test process imports
(the folder mechdyn comes from and this one on their ``PYTHONPATH``, so an element
class of a test module, such as ``test_custom_element.PreloadedSpring``, is importable
there, as a user's own module would be installed on a cluster's workers) and share its compile cache
(``MECHDYN_CACHE``) unless a worker is given another.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from mounts import confined

IDLE = 300             # s: the scheduler ends after this long without work
DEATH = 30             # s: a worker ends after this long without its scheduler
START_TIMEOUT = 60     # s: for the scheduler's file and the workers to register
HERE = Path(__file__).resolve().parent


def dask_command(*arguments) -> list:
    """``dask ARGUMENTS`` of the running Python's environment."""
    script = Path(sys.executable).with_name("dask")
    if script.is_file():
        return [str(script), *arguments]
    return [sys.executable, "-m", "dask", *arguments]


class Cluster:
    """A scheduler and its workers; ``address`` for ``--dask`` and ``Client``."""

    def __init__(self, folder):
        from filelock import FileLock
        self.folder = Path(folder)
        self._machine_lock = FileLock(str(Path(tempfile.gettempdir())
                                          / "mechdyn-test-dask-cluster.lock"))
        self._machine_lock.acquire(timeout=600)
        self.scheduler, self.workers, self.address = None, [], None

    # ------------------------------------------------------------------ processes
    def start(self, workers=2):
        file = self.folder / "scheduler.json"
        self.scheduler = self._spawn("scheduler", dask_command(
            "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
            "--scheduler-file", str(file), "--idle-timeout", f"{IDLE}s"))
        deadline = time.monotonic() + START_TIMEOUT
        while not file.is_file():
            self._alive_or_fail(self.scheduler, deadline)
            time.sleep(0.05)
        while self.address is None:
            try:
                self.address = json.loads(file.read_text())["address"]
            except (ValueError, KeyError):          # still being written
                self._alive_or_fail(self.scheduler, deadline)
                time.sleep(0.05)
        for _ in range(workers):
            self.add_worker()
        if workers:
            self.wait_for_workers(workers)
        return self

    def add_worker(self, env=None, confine=None):
        """Start one ``dask worker`` (a nanny and its worker process); ``env``: more
        environment variables (e.g. another ``MECHDYN_CACHE``); ``confine``: a pair
        ``(folder, how)`` or ``(folder, how, seed)`` for :func:`confined`."""
        number = len(self.workers) + 1
        wrap = (lambda command: confined(command, *confine)) if confine else list
        self.workers.append(self._spawn(f"worker{number}", wrap(dask_command(
            "worker", self.address, "--nthreads", "1", "--no-dashboard",
            "--host", "127.0.0.1", "--death-timeout", f"{DEATH}s",
            "--local-directory", str(self.folder / f"worker{number}"))), env))
        return self.workers[-1]

    def wait_for_workers(self, count):
        with self.client() as client:
            client.wait_for_workers(count, timeout=START_TIMEOUT)

    def client(self):
        from distributed import Client
        return Client(self.address, timeout=START_TIMEOUT)

    def kill_scheduler(self):
        _end_group(self.scheduler, signal.SIGKILL)

    def restart(self, workers=2):
        """End every process and start a new scheduler (another address) and workers."""
        self._end_all()
        self.scheduler, self.workers, self.address = None, [], None
        (self.folder / "scheduler.json").unlink(missing_ok=True)
        return self.start(workers)

    def close(self):
        try:
            self._end_all()
        finally:
            self._machine_lock.release()

    def log(self, name) -> str:
        """What the process ``name`` (``scheduler``, ``worker1``, ...) printed."""
        return (self.folder / f"{name}.log").read_text(errors="replace")

    # ------------------------------------------------------------------ internals
    def _spawn(self, name, command, env=None):
        import mechdyn
        path = os.pathsep.join(filter(None, [str(HERE), str(Path(mechdyn.__file__).parents[1]),
                                             os.environ.get("PYTHONPATH")]))
        environment = {**os.environ, "PYTHONPATH": path, **(env or {})}
        with open(self.folder / f"{name}.log", "wb") as log:
            return subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT,
                                    stdin=subprocess.DEVNULL, env=environment,
                                    cwd=self.folder, start_new_session=True)

    def _end_all(self):
        for process in [*self.workers, self.scheduler]:
            if process is not None:
                _end_group(process, signal.SIGTERM)

    def _alive_or_fail(self, process, deadline):
        if process.poll() is not None or time.monotonic() > deadline:
            raise RuntimeError(f"the dask scheduler did not start:\n{self.log('scheduler')}")


def _end_group(process, first):
    """End ``process`` and everything in its process group: ``first``, then SIGKILL."""
    for sig in (first, signal.SIGKILL):
        try:
            os.killpg(process.pid, sig)
        except ProcessLookupError:
            return
        try:
            process.wait(timeout=10)
            if sig == signal.SIGKILL or _group_gone(process.pid):
                return
        except subprocess.TimeoutExpired:
            continue


def _group_gone(group) -> bool:
    try:
        os.killpg(group, 0)
    except ProcessLookupError:
        return True
    return False
