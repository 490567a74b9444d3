"""Parameter sweeps: run one scene over a grid of parameter values on any Executor.

The equations are derived and compiled once, in the calling process, with the compiled
kernels' form of the scene, which the points then run on (``backend="auto"``): the disk
cache then serves every worker that shares it. The workers receive the mechanism, the
scene and the generated code (local processes: when they start; other executors: with
each task, unpickled once per worker), so they neither derive nor compile. Any
:class:`concurrent.futures.Executor` runs the points. By default (no ``executor``, no
``workers``) the points run in the calling process for ``HERE_SECONDS`` first (a
compiled point takes well under a millisecond, and starting a worker process costs
about a second), and local processes, one per core, take what is left; a Dask cluster
through ``distributed.Client(...).get_executor()`` (``docs/cluster.md``).

Limits and faults:

- the grid may hold at most ``max_points`` points (default 1,000,000, about 1 KB of
  memory per row); points go to the workers in batches of about 0.1 s of work, at most
  ``IN_FLIGHT`` batches (four per local worker) submitted at a time
  (:mod:`mechdyn.analyse.sweep_tasks`); a worker that cannot import an element class is
  refused before the first row; a lost executor (a Dask scheduler) stops the sweep with
  a ``SweepError``, the finished rows kept;
- each finished point is appended to the ``out`` CSV file at once (see
  :mod:`mechdyn.analyse.sweep_file`: locked, and recorded so a rerun resumes only the same
  sweep); a crash or Ctrl-C loses only the points in flight;
- on Ctrl-C (or any error) the local worker processes are ended at once; they ignore
  SIGINT themselves and end on their own within a second if the main process is killed.

The grid's values are checked once for all points
(:meth:`~mechdyn.declare.parameters.ParameterSet.refused_points`: a refused point's row
keeps the error ``simulate`` raises for it), and a point runs from a template of the
parameter vector (:class:`~mechdyn.simulate.repeated.RepeatedRuns`). A point whose
simulation fails is recorded with its error text (and not retried by a rerun: delete its
row to retry); the other points are kept.

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

import itertools
import math
import pickle
import time

import numpy as np

from mechdyn.declare.parameters import ParameterSet
from mechdyn.analyse.sweep_file import MAX_POINTS, TEXT_COLUMNS, SweepError, SweepFile, SweepFileError
from mechdyn.analyse.sweep_grid import Plan, grid_points, record_of
from mechdyn.analyse.sweep_points import _Job, _load_kernels, _row
from mechdyn.analyse.sweep_tasks import IN_FLIGHT, run_batches
from mechdyn.simulate.threads import single_threaded_blas

__all__ = ["sweep", "Sweep", "SweepError", "SweepFileError", "MAX_POINTS", "IN_FLIGHT"]


HERE_SECONDS = 1.0           # default: points run in the calling process this long first
SHOWN_ROWS = 40              # rows print(sweep) shows, at most


def sweep(mechanism, scene, params, grid, executor=None, out=None, progress=True, *,
          workers=None, max_points=MAX_POINTS, fresh=False, wait=0.0, measures=None,
          steady=None, cycle=2 * math.pi):
    """Simulate ``scene`` (or find its steady running) at every point of a
    full-factorial parameter grid and measure each.

    Parameters
    ----------
    mechanism : Mechanism
    scene : Scene
    params : dict
        Values of all parameters (symbols or names); the swept ones are overridden.
    grid : dict
        Parameter (symbol or name) -> list of values; all combinations are run.
    executor : concurrent.futures.Executor, optional
        Runs the points (default: ``workers`` local processes, ended afterwards). A
        Dask cluster's ``client.get_executor()`` works unchanged.
    out : str or Path, optional
        CSV file the rows are appended to as they finish; an existing file of the same
        sweep is resumed, one of another sweep refused (see :mod:`mechdyn.analyse.sweep_file`).
    progress : bool
        Show a tqdm progress bar (when tqdm is installed and the output is a terminal).
    workers : int, optional
        Local worker processes when no ``executor`` is given (default: the calling
        process for the first ``HERE_SECONDS``, then one process per core).
    max_points : int
        Refuse grids with more points (default :data:`MAX_POINTS`).
    fresh : bool
        Discard the rows of an existing ``out`` file instead of resuming it.
    wait : float
        Seconds to wait for another sweep that holds ``out`` (default: stop at once).
    measures : list, optional
        Measures (:func:`~mechdyn.analyse.measures.measure`: names such as
        ``"fluctuation"``, ``"peak:motor"``, or functions of an outcome), a column each.
    steady : bool, optional
        Measure steady running (:func:`~mechdyn.analyse.fluctuation.steady_running`
        over ``cycle`` rad, from the scene's initial speed) instead of a run; None:
        when a measure of steady running (``mean_speed``, ``fluctuation``,
        ``cycle_time``) is asked for.

    Returns
    -------
    Sweep
        The rows in grid order: the parameters, a column per measure (default, of a
        run: ``t_end``, ``final:STATE`` per coordinate and speed, ``peak:OUTPUT`` per
        output; of steady running: ``mean_speed``, ``fluctuation``, ``peak:OUTPUT``),
        ``reason`` (a run's), ``error`` (empty if ok; a measure that fails is NaN and
        its error is kept here, the others kept).

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
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or workers < 1):
        raise SweepError(f"sweep: workers = {workers!r} must be a whole number >= 1")
    from mechdyn.compile.compiler import compile_scene
    values = ParameterSet(params, mechanism=mechanism, scene=scene)   # before any compiling
    compiled = compile_scene(mechanism, scene)
    plan = Plan.of(mechanism, scene, measures, steady, cycle, values)
    names, points = grid_points(grid, compiled, max_points, mechanism.parameter_units)
    fixed_names = [n for n in compiled.param_names if n not in names]
    derived = values.depending_on(names)      # they change with the swept values
    fixed = {name: str(derived[name]) if name in derived else value
             for name, value in zip(fixed_names, values.vector(fixed_names))}
    columns = plan.columns(names)
    record = record_of(mechanism, scene, compiled, names, fixed, plan)
    with SweepFile(out, columns, names, record, fresh=fresh, wait=wait) as table:
        todo = [point for point in points if point not in table.rows]
        if todo:
            refused = values.refused_points(names, todo)   # checked at once, not per point
            job = _Job(mechanism, scene, {**values.numbers, **derived}, tuple(names),
                       compiled.key, compiled.meta, compiled.source,
                       {todo[index]: error for index, error in refused.items()}, plan)
            blob = _pickled(job, mechanism)     # before any row: workers unpickle it
            bar = _bar(progress, len(points), len(table.rows))
            if plan.cycle is None:                # runs: the compiled scene, loaded once
                _load_kernels(compiled, scene)    # before any point or worker
            if executor is None and workers is None and plan.cycle is None:
                todo = _run_here(job, todo, table, bar, HERE_SECONDS)
            if todo:
                run_batches(blob, todo, table, executor or workers, bar,
                            _foreign_classes(mechanism))
        rows = [table.rows[point] for point in points]
    return Sweep(names, columns, rows, plan.default_y, out, plan.units(mechanism, names))


class Sweep:
    """The rows of a sweep in grid order, with column access and a plot.

    ``sweep[column]`` is an array (floats; strings for ``reason`` and ``error``);
    ``rows`` the dicts; ``failed`` the rows whose simulation failed; ``parameters`` the
    swept names; ``path`` the CSV file (or None); ``units`` the SI unit of each column
    (``""`` where it has none or it is not known), ``label(column)`` ``"P [N]"``.
    ``print(sweep)`` prints it as a table (``table()``), Jupyter renders it as one.

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> table = md.sweep(model.mechanism, model.scenes["braking"], model.params,
    ...                  {"P": [20, 50]}, progress=False)
    >>> len(table), table.parameters, table.failed
    (2, ['P'], [])
    >>> table["t_end"].round(9), table.label("t_end")       # I omega_0 / (2 f P R)
    (array([50., 20.]), 't_end [s]')
    """

    def __init__(self, parameters, columns, rows, default_y, path=None, units=None):
        self.parameters, self.columns, self.rows = list(parameters), list(columns), rows
        self.default_y, self.path = default_y, path
        self.units = dict(units or {})

    def label(self, column) -> str:
        """``column [unit]`` (the values' SI unit), or the column alone."""
        unit = self.units.get(column, "")
        return f"{column} [{unit}]" if unit else column

    def __len__(self):
        return len(self.rows)

    def __getitem__(self, column):
        if column not in self.columns:
            raise KeyError(f"{column!r}: not a column ({', '.join(self.columns)})")
        values = [row[column] for row in self.rows]
        return np.array(values, dtype=object if column in TEXT_COLUMNS else float)

    @property
    def failed(self) -> list:
        return [row for row in self.rows if row["error"]]

    def plot(self, y=None, path=None):
        """An output (default: ``t_end`` if the scene stops, else a peak) against the
        first swept parameter, a line per value of the others; saved to ``path``."""
        from mechdyn.plotting import plot_sweep
        return plot_sweep(self, y or self.default_y, path)

    def table(self, rows=SHOWN_ROWS):
        """The rows as a :class:`~mechdyn.tabular.Table` (headers with units; the
        first and last ``rows // 2`` rows of a longer sweep, the caption saying so)."""
        from mechdyn.tabular import Table
        columns = [c for c in self.columns if c != "error" or self.failed]
        chosen = list(enumerate(self.rows))
        caption = f"sweep over {', '.join(self.parameters)}: {len(self.rows)} points"
        if len(chosen) > rows:
            chosen = chosen[:rows // 2] + chosen[len(chosen) - rows // 2:]
            caption += f" (rows {rows // 2 + 1} to {len(self.rows) - rows // 2} left out)"
        cells = [[_cell(row[c], c) for c in columns] for _, row in chosen]
        return Table([self.label(c) for c in columns], cells, caption)

    def __str__(self):
        return self.table().text()

    def _repr_html_(self):
        return self.table()._repr_html_()

    def __repr__(self):
        return (f"<Sweep over {', '.join(self.parameters)}: {len(self.rows)} points, "
                f"{len(self.failed)} failed>")


def _cell(value, column):
    """A table cell: a number, a missing value (None) or text cut to a line."""
    if column in TEXT_COLUMNS:
        return value if len(value) <= 60 else value[:57] + "..."
    return None if np.isnan(value) else value


def _run_here(job, todo, table, bar, seconds) -> list:
    """Run points in the calling process for about ``seconds``: the points left (the
    bar is closed when none are left, or on an interruption)."""
    started, left = time.perf_counter(), []
    try:
        with single_threaded_blas():   # set once for the points, not once per point
            for done, point in enumerate(todo):
                if time.perf_counter() - started > seconds:
                    left = todo[done:]
                    break
                table.add(_row(job, point))
                if bar is not None:
                    bar.update()
    finally:
        if bar is not None and not left:
            bar.close()
    return left


def _pickled(job, mechanism) -> bytes:
    """The job as the workers receive it; an element class they could not unpickle (one
    defined inside a function) is refused by name before the first row."""
    try:
        return pickle.dumps(job)
    except (pickle.PicklingError, AttributeError, TypeError) as error:
        culprits = [f"{type(e).__name__.lower()} {name!r}" for name, e in
                    mechanism.elements.items() if not _can_pickle(e)]
        culprits += [f"measure {m.name!r}" for m in job.plan.measures if not _can_pickle(m)]
        raise SweepError(
            f"sweep: {', '.join(culprits) or 'the mechanism or scene'} cannot be pickled "
            f"for the sweep's worker processes ({error}); define the element class (or "
            "the measure's function) at module level in an importable module, not inside "
            "a function") from error


def _foreign_classes(mechanism) -> list:
    """The mechanism's element classes defined outside mechdyn (a worker must import
    them to unpickle the job)."""
    classes = {type(e) for e in mechanism.elements.values()}
    return sorted((c for c in classes if not c.__module__.startswith("mechdyn.")),
                  key=lambda c: (c.__module__, c.__qualname__))


def _can_pickle(value) -> bool:
    try:
        pickle.dumps(value)
    except (pickle.PicklingError, AttributeError, TypeError):
        return False
    return True


def _bar(show, total, initial):
    """A tqdm progress bar, or None without tqdm (an optional dependency)."""
    if not show:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    return tqdm(total=total, initial=initial, unit="point", desc="sweep", disable=None)
