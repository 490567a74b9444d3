"""A sweep's points as tasks on an executor: batches sized from the measured cost of a
point, rows recorded as each batch finishes, the finished rows kept on any failure.

Local worker processes receive the pickled job when they start; any other executor (a
Dask cluster's ``client.get_executor()``) receives it with every task, so a worker
that joins late, or replaces a killed one, unpickles it once and then runs its points.
On such an executor a first task without points checks that a worker can load the job
(import the element classes, load the compiled scene), so a class the workers cannot
import is refused before the first row. Then a few tasks of ``_PROBE_POINTS`` points
measure a point's cost, and every later task carries about ``BATCH_SECONDS`` of work:
a task's round trip through a scheduler (a millisecond or more) stays a small part of
it; near the end a task takes at most an eighth of the points left (and at least a
quarter of a full task's), so that the workers finish together. A task the executor loses (a killed worker) is the executor's
to retry (Dask does); one it cancels or fails (a lost scheduler) stops the sweep with a
``SweepError`` saying that the finished rows are kept and a rerun resumes.

>>> batch = _Batch()
>>> batch.learn(0.002, 4)              # 0.5 ms a point: 0.1 s is 200 points
>>> batch.size
200
"""
from __future__ import annotations

import hashlib
import os
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

from mechdyn.errors import MechdynError
from mechdyn.analyse.sweep_file import SweepError
from mechdyn.analyse.sweep_points import _WorkerSetupError, _run_points, _start_worker

__all__ = ["run_batches", "IN_FLIGHT", "BATCH_SECONDS"]

IN_FLIGHT = 512              # tasks submitted and not yet collected, at most
BATCH_SECONDS = 0.1          # work per task once the cost of a point is known
_MAX_BATCH = 1000            # points per task, at most
_PROBE_POINTS = 12           # points per task until a point's cost is measured
_PROBES = 2                  # such tasks in flight at once (an executor of our own: one a worker)
_TAIL_SHARES = 8             # a task takes at most this share of the points left: an even finish
_TAIL_FLOOR = 4              # ... and at least this share of a full task's points


def run_batches(blob, todo, table, executor, bar, classes=()):
    """Run the points ``todo`` in batches and add each row to ``table`` as its batch
    finishes; on any interruption keep the finished rows, cancel the rest and end the
    local workers. ``executor``: an Executor, or the number of local workers (None: one
    per core); ``blob`` the pickled job; ``classes`` the element classes defined outside
    mechdyn, named when a worker cannot load the job."""
    digest = hashlib.sha256(blob).hexdigest()
    own = not hasattr(executor, "submit")
    limit, probes = IN_FLIGHT, _PROBES
    if own:
        count = min(len(todo), executor or os.cpu_count() or 1)
        executor = ProcessPoolExecutor(max_workers=count, initializer=_start_worker,
                                       initargs=(digest, blob))
        limit = probes = 4 * count
    shipped = None if own else blob               # own workers got the job at start
    pending, finished, batch, sent = set(), False, _Batch(), 0
    order = {}                          # future -> submission number: rows in grid order
    # Before any row: can a worker load the job? (the first batches, sent at once, set
    # up the other workers meanwhile; their rows are not kept if it cannot)
    check = None if own else executor.submit(_run_points, digest, blob, [])
    try:
        while True:
            while sent < len(todo) and len(pending) < (limit if batch.known else probes):
                tail = -((sent - len(todo)) // _TAIL_SHARES)              # ceil
                size = min(batch.size, max(tail, batch.size // _TAIL_FLOOR))
                future = executor.submit(_run_points, digest, shipped, todo[sent:sent + size])
                sent += size
                order[future] = len(order)
                pending.add(future)
            if check is not None:
                _collect(wait([check])[0], table, bar, batch, classes)
                check = None
            if not pending:
                break
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            _collect(sorted(done, key=order.pop), table, bar, batch, classes)
        finished = True
    finally:
        for future in pending:
            future.cancel()
        if check is None:
            _collect(sorted((f for f in pending if f.done() and not f.cancelled()
                             and f.exception() is None), key=order.get), table, bar, batch)
        if bar is not None:
            bar.close()
        if own:
            if not finished:
                _end_workers(executor)
            executor.shutdown(wait=True, cancel_futures=True)


class _Batch:
    """Points per submitted task: ``_PROBE_POINTS`` until a point's cost is measured,
    then as many as take about ``BATCH_SECONDS`` (from all points timed so far), so the
    cost of a task's round trip vanishes beside its work."""

    def __init__(self):
        self.size, self.known, self._seconds, self._points = _PROBE_POINTS, False, 0.0, 0

    def learn(self, seconds, points):
        if points < 1:
            return
        self._seconds += seconds
        self._points += points
        per_point = max(self._seconds / self._points, 1e-6)
        self.size = max(1, min(_MAX_BATCH, int(BATCH_SECONDS / per_point)))
        self.known = True


def _collect(futures, table, bar, batch, classes=()):
    """Add the rows of the finished ``futures`` (in their order) to ``table``; then raise
    the first failure among them, if any."""
    failure = None
    for future in futures:
        try:
            rows, seconds, timed = _outcome(future, table, classes)
        except BaseException as error:
            failure = failure or error
            continue
        batch.learn(seconds, timed)
        for row in rows:
            table.add(row)
            if bar is not None:
                bar.update()
    if failure is not None:
        raise failure


def _outcome(future, table, classes):
    """A finished task's result, or the SweepError that says what went wrong and that
    the finished rows are kept."""
    kept = ("the finished rows are kept"
            + (f" in {table.path}" if getattr(table, "path", None) else "")
            + "; rerun the same sweep to resume")
    if future.cancelled():
        raise SweepError("sweep: the executor cancelled a batch of points (a Dask "
                         f"scheduler lost, or its client closed); {kept}")
    error = future.exception()
    if error is None:
        return future.result()
    if isinstance(error, _WorkerSetupError):
        raise SweepError(_cannot_load(error, classes)) from error
    if isinstance(error, (MechdynError, KeyboardInterrupt)):
        raise error
    raise SweepError(f"sweep: the executor failed ({type(error).__name__}: {error}); "
                     f"{kept}") from error


def _cannot_load(error, classes) -> str:
    """What to do when a worker cannot unpickle the job."""
    named = ", ".join(f"{c.__module__}.{c.__qualname__}" for c in classes)
    script = [c.__qualname__ for c in classes if c.__module__ == "__main__"]
    return ("sweep: a worker cannot load the sweep (" + str(error) + "); every worker "
            "must import the mechanism's element classes"
            + (f" ({named})" if named else "")
            + (f": {', '.join(script)} is defined in the script that runs (__main__), "
               "which a worker does not import; move it into a module" if script else "")
            + ": install their module where the workers run (pip install, or its folder "
            "on the workers' PYTHONPATH; Dask: client.upload_file('module.py')), or run "
            "the sweep on local workers (workers=N, --workers N)")


def _end_workers(executor):
    """Terminate a ProcessPoolExecutor's workers now (their points are lost anyway)."""
    terminate = getattr(executor, "terminate_workers", None)       # Python >= 3.14
    if terminate is not None:
        terminate()
        return
    for process in list((getattr(executor, "_processes", None) or {}).values()):
        process.terminate()
