"""Parameter sweeps: run one scene over a grid of parameter values on any Executor.

The equations are derived and compiled once, in the calling process; the workers receive
the mechanism, the scene and the generated code (pickled once per sweep), so they neither
derive nor compile. Any :class:`concurrent.futures.Executor` runs the points: local
processes by default, a Dask cluster through ``distributed.Client(...).get_executor()``.

Each finished point is appended to the ``out`` CSV file at once, so a crash loses only
the points in flight; a rerun with the same ``out`` reads the file and runs only the
points not in it. A point whose simulation fails is recorded with its error text (and
not retried by a rerun: delete its row to retry); the other points are kept.

>>> import mechdyn as md
>>> from concurrent.futures import ThreadPoolExecutor
>>> model = md.load_model("models/shoe_brake.py")
>>> with ThreadPoolExecutor(2) as pool:
...     table = md.sweep(model.mechanism, model.scenes["braking"], model.params,
...                      {"P": [10, 20, 40]}, executor=pool, progress=False)
>>> table["t_end"].round(9).tolist()        # t = I omega_0 / (2 f P R) = 1000 / P
[100.0, 50.0, 25.0]
"""
from __future__ import annotations

import csv
import hashlib
import itertools
import os
import pickle
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .compile import CompiledScene, compile_scene
from .errors import MechdynError, ParameterError
from .plotting import dense_series

__all__ = ["sweep", "Sweep", "SweepFileError"]

_TEXT_COLUMNS = ("reason", "error")


class SweepFileError(MechdynError, ValueError):
    """An ``out`` file that holds a different sweep's columns."""


def sweep(mechanism, scene, params, grid, executor=None, out=None, progress=True):
    """Simulate ``scene`` at every point of a full-factorial parameter grid.

    Parameters
    ----------
    mechanism : Mechanism
    scene : Scene
    params : dict
        Values of all parameters (symbols or names); the swept ones are overridden.
    grid : dict
        Parameter (symbol or name) -> list of values; all combinations are run.
    executor : concurrent.futures.Executor, optional
        Runs the points (default: a ``ProcessPoolExecutor`` on all cores, shut down
        afterwards). A Dask cluster's ``client.get_executor()`` works unchanged.
    out : str or Path, optional
        CSV file the rows are appended to as they finish; an existing file is resumed.
    progress : bool
        Show a tqdm progress bar (when tqdm is installed and the output is a terminal).

    Returns
    -------
    Sweep
        The rows in grid order: the parameters, ``t_end``, ``reason``, ``final:STATE``
        per coordinate and speed, ``peak:OUTPUT`` per output, ``error`` (empty if ok).

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("models/shoe_brake.py")
    >>> table = md.sweep(model.mechanism, model.scenes["braking"], model.params,
    ...                  {"P": [20, 50]}, progress=False)
    >>> table.columns
    ['P', 't_end', 'reason', 'final:phi', 'final:phidot', 'error']
    >>> table["final:phi"].round(6).tolist()    # omega_0^2 / (2 eps), eps = 2 f P R / I
    [2500.0, 1000.0]
    """
    compiled = compile_scene(mechanism, scene)
    names, points = _grid_points(grid, compiled)
    base = {str(key): value for key, value in params.items()}
    compiled.parameter_vector({**base, **dict.fromkeys(names, 0.0)})  # all known?
    columns = _columns(names, compiled)
    table = _Table(out, columns, names)
    todo = [point for point in points if point not in table.rows]
    try:
        if todo:
            job = _Job(mechanism, scene, base, tuple(names), compiled.key, compiled.meta,
                       compiled.source)
            _run(job, todo, table, executor, _bar(progress, len(points), len(table.rows)))
    finally:
        table.close()
    default_y = "t_end" if scene.until else next(
        (c for c in columns if c.startswith("peak:")), f"final:{compiled.state_names[-1]}")
    return Sweep(names, columns, [table.rows[point] for point in points], default_y, out)


class Sweep:
    """The rows of a sweep in grid order, with column access and a plot.

    ``sweep[column]`` is an array (floats; strings for ``reason`` and ``error``);
    ``rows`` the dicts; ``failed`` the rows whose simulation failed; ``parameters`` the
    swept names; ``path`` the CSV file (or None).
    """

    def __init__(self, parameters, columns, rows, default_y, path=None):
        self.parameters, self.columns, self.rows = list(parameters), list(columns), rows
        self.default_y, self.path = default_y, path

    def __len__(self):
        return len(self.rows)

    def __getitem__(self, column):
        if column not in self.columns:
            raise KeyError(f"{column!r}: not a column ({', '.join(self.columns)})")
        values = [row[column] for row in self.rows]
        return np.array(values, dtype=object if column in _TEXT_COLUMNS else float)

    @property
    def failed(self) -> list:
        return [row for row in self.rows if row["error"]]

    def plot(self, y=None, path=None):
        """An output (default: ``t_end`` if the scene stops, else a peak) against the
        first swept parameter, a line per value of the others; saved to ``path``."""
        from .plotting import plot_sweep
        return plot_sweep(self, y or self.default_y, path)

    def __repr__(self):
        return (f"<Sweep over {', '.join(self.parameters)}: {len(self.rows)} points, "
                f"{len(self.failed)} failed>")


# ---------------------------------------------------------------------- the grid
def _grid_points(grid, compiled):
    """Swept names (checked against the scene's parameters) and the grid's points."""
    if not grid:
        raise ParameterError("sweep: the grid is empty; give {parameter: [values]}")
    names, axes = [], []
    for key, values in grid.items():
        name = str(key)
        if name not in compiled.param_names:
            raise ParameterError(f"sweep: {name!r} is not a parameter of this scene "
                                 f"(parameters: {', '.join(compiled.param_names)})")
        try:
            values = [float(v) for v in values]
        except (TypeError, ValueError):
            raise ParameterError(f"sweep: the values of {name} must be numbers") from None
        if not values or not all(np.isfinite(values)):
            raise ParameterError(f"sweep: give {name} at least one finite value")
        names.append(name)
        axes.append(values)
    return names, list(dict.fromkeys(itertools.product(*axes)))


def _columns(names, compiled):
    columns = names + ["t_end", "reason"]
    columns += [f"final:{state}" for state in compiled.state_names]
    columns += [f"peak:{label}" for label in compiled.output_labels]
    clash = set(names) & set(columns[len(names):] + ["error"])
    if clash:
        raise ParameterError(f"sweep: parameter {sorted(clash)} clashes with a result column")
    return columns + ["error"]


# ------------------------------------------------------------------ the workers
@dataclass(frozen=True)
class _Job:
    """What every point needs: pickled once per sweep, unpickled once per worker."""
    mechanism: object
    scene: object
    params: dict
    names: tuple
    key: str
    meta: dict
    source: str


_jobs: dict = {}          # per worker process: digest -> _Job


def _run_point(digest, blob, point):
    """Simulate one grid point in a worker; a failure becomes the row's ``error``."""
    job = _jobs.get(digest)
    if job is None:
        job = _jobs[digest] = pickle.loads(blob)
        # Hand the parent's generated code to compile_scene's cache: no derivation here.
        from . import compile as compile_module
        compile_module._memory_cache.setdefault(
            job.key, CompiledScene(job.meta, job.source, job.key))
    row = dict(zip(job.names, point))
    try:
        result = job.mechanism.simulate(job.scene, {**job.params, **row})
    except Exception as error:          # recorded in the row; the sweep goes on
        row["error"] = f"{type(error).__name__}: {error}"
        return row
    row.update(t_end=result.t_end, reason=result.reason, error="")
    for name, values in zip(result.state_names, result.y):
        row[f"final:{name}"] = float(values[-1])
    for label, values in dense_series(result)[2].items():
        row[f"peak:{label}"] = float(values[np.argmax(np.abs(values))])
    return row


def _run(job, todo, table, executor, bar):
    """Submit the points, record each as it finishes; on any interruption keep the
    finished ones and cancel the rest."""
    blob = pickle.dumps(job)
    digest = hashlib.sha256(blob).hexdigest()
    own = executor is None
    if own:
        executor = ProcessPoolExecutor(max_workers=min(len(todo), os.cpu_count() or 1))
    order, pending = {}, set()          # futures by submission, to write in grid order
    try:
        for point in todo:
            future = executor.submit(_run_point, digest, blob, point)
            order[future] = len(order)
            pending.add(future)
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            _record(sorted(done, key=order.get), table, bar)
    finally:
        for future in pending:
            future.cancel()
        _record(sorted((f for f in pending if f.done() and not f.cancelled()
                        and f.exception() is None), key=order.get), table, bar)
        if bar is not None:
            bar.close()
        if own:
            executor.shutdown(wait=True, cancel_futures=True)


def _record(futures, table, bar):
    for future in futures:
        table.add(future.result())
        if bar is not None:
            bar.update()


def _bar(show, total, initial):
    """A tqdm progress bar, or None without tqdm (an optional dependency)."""
    if not show:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    return tqdm(total=total, initial=initial, unit="point", desc="sweep", disable=None)


# --------------------------------------------------------------- the results file
class _Table:
    """Rows by grid point, appended to a CSV file as they arrive (resumed if present)."""

    def __init__(self, path, columns, names):
        self.columns, self.names, self.rows = columns, names, {}
        self._handle = self._writer = None
        if path is None:
            return
        path = Path(path)
        if path.is_file() and path.stat().st_size:
            self._resume(path)
            self._handle = open(path, "a", newline="")
            self._writer = csv.writer(self._handle)
        else:
            self._handle = open(path, "w", newline="")
            self._writer = csv.writer(self._handle)
            self._writer.writerow(columns)
            self._handle.flush()

    def _resume(self, path):
        text = path.read_text()
        if not text.endswith("\n"):              # a row cut off by a crash
            text = text[:text.rfind("\n") + 1]
            path.write_text(text)
        lines = list(csv.reader(text.splitlines()))
        if not lines or lines[0] != self.columns:
            found = ", ".join(lines[0]) if lines else "nothing"
            raise SweepFileError(f"{path} holds another sweep (columns {found}); expected "
                                 f"{', '.join(self.columns)}: give a new --out file")
        for values in lines[1:]:
            if len(values) == len(self.columns):
                self.add(dict(zip(self.columns, values)), write=False)

    def add(self, row, write=True):
        row = {c: _value(c, row.get(c, "")) for c in self.columns}
        self.rows[tuple(row[n] for n in self.names)] = row
        if write and self._writer is not None:
            self._writer.writerow([_text(v) for v in row.values()])
            self._handle.flush()

    def close(self):
        if self._handle is not None:
            self._handle.close()


def _text(value):
    if isinstance(value, float):
        return "" if np.isnan(value) else repr(value)
    return value


def _value(column, value):
    if column in _TEXT_COLUMNS:
        return str(value)
    return float(value) if value != "" else float("nan")
