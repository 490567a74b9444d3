"""A sweep's points: what a worker (or the calling process) does with each.

The job (mechanism, scene, fixed values, generated code) is pickled once per sweep and
unpickled once per worker, whose ``compile_scene`` memory cache then holds the scene's
generated code and whose kernels load its compiled form from the disk cache
(:func:`_load_kernels`): a worker neither derives nor compiles. A point's row holds the
swept values, the sweep's measures of its run or steady cycle
(:mod:`mechdyn.analyse.sweep_grid`), a run's ``reason`` and ``error`` (a failing
point's message; the sweep goes on). A worker whose scene has another key
than the calling process's (an element reads a value changed there in place) fails
each point with that said, instead of running other code. See
:mod:`mechdyn.analyse.sweeps`.
"""
from __future__ import annotations

import os
import pickle
import signal
import socket
import threading
import time
import weakref
from dataclasses import dataclass, field

from mechdyn.simulate.repeated import RepeatedRuns
from mechdyn.simulate.threads import single_threaded_blas

_PARENT_CHECK = 0.5          # s between a worker's checks that its parent still lives


@dataclass(frozen=True, eq=False)     # hashed by identity: a key of _runs
class _Job:
    """What every point needs: pickled once per sweep, unpickled once per worker."""
    mechanism: object
    scene: object
    params: dict
    names: tuple
    key: str
    meta: dict
    source: str
    refused: dict = field(default_factory=dict)   # point -> its ParameterError
    plan: object = None                  # :class:`~mechdyn.analyse.sweep_grid.Plan`


_jobs: dict = {}          # per worker process: digest -> _Job
_OTHER_CODE = ("the mechanism gives other equations in this worker process than in the "
               "calling one (an element's work() reads a value that was changed in the "
               "calling process after its module was imported?); run the sweep with "
               "workers=1, or change the value in the module itself")


def _install(digest, blob):
    """Unpickle a job once per worker and hand its generated code to compile_scene's
    memory cache: no derivation, no compilation, no disk in the worker."""
    job = _jobs.get(digest)
    if job is None:
        job = _jobs[digest] = pickle.loads(blob)
        from mechdyn.compile import compiler as compile_module
        compiled = compile_module._memory_cache.setdefault(
            job.key, compile_module.CompiledScene(job.meta, job.source, job.key))
        if job.plan.cycle is None:          # steady running integrates on scipy
            _load_kernels(compiled, job.scene)
    return job


def _start_worker(digest, blob):
    """A local worker: Ctrl-C is the parent's to handle; end with the parent."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=_end_with_parent, args=(os.getppid(),), daemon=True).start()
    _install(digest, blob)


def _end_with_parent(parent):
    """Exit as soon as the parent process is gone (killed: we were re-parented)."""
    while os.getppid() == parent:
        time.sleep(_PARENT_CHECK)
    os._exit(1)


class _WorkerSetupError(RuntimeError):
    """A worker that cannot unpickle the sweep's job (an element class it cannot import)
    or load its compiled form; raised in the worker, turned into a ``SweepError`` that
    says what to do by the calling process."""


def _run_points(digest, blob, points):
    """Simulate a batch of grid points in a worker: their rows, and the seconds and
    count of the points timed (all but the first of a batch of several: its point may
    set up the worker's template, which is no point's cost). An empty batch only installs
    the job: the sweep's check that a worker can load it."""
    if blob is None:
        job = _jobs[digest]
    else:
        try:
            job = _install(digest, blob)
        except Exception as error:
            raise _WorkerSetupError(f"{type(error).__name__}: {error} (in process "
                                    f"{os.getpid()} on {socket.gethostname()})") from None
    with single_threaded_blas():       # set once for the batch, not once per point
        rows = [_row(job, point) for point in points[:1]]
        started = time.perf_counter()
        rows += [_row(job, point) for point in points[1:]]
        seconds = time.perf_counter() - started
    return rows, seconds, max(len(points) - 1, 0)


def _row(job, point) -> dict:
    """One grid point's row; a failure becomes the row's ``error``, a measure that
    fails is NaN with its error there and the others are kept."""
    if point in job.refused:
        return _failed_row(job.names, point, job.refused[point])
    row = dict(zip(job.names, point))
    try:
        outcome = _outcome(job, point, row)
    except Exception as error:          # recorded in the row; the sweep goes on
        return _failed_row(job.names, point, error)
    errors = []
    for measure in job.plan.measures:
        try:
            row[measure.name] = measure(outcome)
        except Exception as error:      # this measure's error; the others are kept
            row[measure.name] = float("nan")
            errors.append(f"{measure.name}: {type(error).__name__}: {error}")
    if job.plan.cycle is None:
        row["reason"] = outcome.reason
    row["error"] = "; ".join(errors)
    return row


def _outcome(job, point, row):
    """The point's run (from the job's parameter template) or steady cycle."""
    if job.plan.cycle is not None:
        from mechdyn.analyse.fluctuation import steady_running
        return steady_running(job.mechanism, job.scene, {**job.params, **row}, job.plan.cycle)
    runs = _repeated_runs(job)
    if runs is not None and runs.compiled.key != job.key:
        raise RuntimeError(_OTHER_CODE)
    if runs is None:
        return job.mechanism.simulate(job.scene, {**job.params, **row})
    return runs.run(point)


def _failed_row(names, point, error) -> dict:
    """The row of a point that failed with ``error``."""
    return {**dict(zip(names, point)), "error": f"{type(error).__name__}: {error}"}


_runs: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()   # _Job -> RepeatedRuns


def _repeated_runs(job):
    """The job's :class:`~mechdyn.simulate.repeated.RepeatedRuns`, set up once per
    process; None where that fails (then each point goes through ``simulate``, which
    raises the point's own error)."""
    if job not in _runs:
        try:
            _runs[job] = RepeatedRuns(job.mechanism, job.scene, job.params, job.names)
        except Exception:
            _runs[job] = None
    return _runs[job]


def _load_kernels(compiled, scene):
    """Compile or load the scene's compiled form once in the calling process (the disk
    cache then serves every worker), where its runs will use it."""
    if scene.backend != "scipy":
        from mechdyn.simulate.methods import uses_kernels
        uses_kernels(compiled, scene.method)
