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

from mechdyn.version import __version__
from mechdyn.errors import ParameterError, did_you_mean
from mechdyn.declare.parameters import ParameterSet, to_number
from mechdyn.analyse.sweep_file import MAX_POINTS, TEXT_COLUMNS, SweepError, SweepFile, SweepFileError
from mechdyn.analyse.sweep_points import _Job, _load_kernels, _row
from mechdyn.analyse.sweep_tasks import IN_FLIGHT, run_batches
from mechdyn.simulate.threads import single_threaded_blas

__all__ = ["sweep", "Sweep", "SweepError", "SweepFileError", "MAX_POINTS", "IN_FLIGHT"]


HERE_SECONDS = 1.0           # default: points run in the calling process this long first


def sweep(mechanism, scene, params, grid, executor=None, out=None, progress=True, *,
          workers=None, max_points=MAX_POINTS, fresh=False, wait=0.0):
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
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or workers < 1):
        raise SweepError(f"sweep: workers = {workers!r} must be a whole number >= 1")
    from mechdyn.compile.compiler import compile_scene
    values = ParameterSet(params, mechanism=mechanism, scene=scene)   # before any compiling
    compiled = compile_scene(mechanism, scene)
    names, points = _grid_points(grid, compiled, max_points, mechanism.parameter_units)
    fixed_names = [n for n in compiled.param_names if n not in names]
    derived = values.depending_on(names)      # they change with the swept values
    fixed = {name: str(derived[name]) if name in derived else value
             for name, value in zip(fixed_names, values.vector(fixed_names))}
    columns = _columns(names, compiled)
    record = _record_of(mechanism, scene, compiled, names, fixed)
    with SweepFile(out, columns, names, record, fresh=fresh, wait=wait) as table:
        todo = [point for point in points if point not in table.rows]
        if todo:
            refused = values.refused_points(names, todo)   # checked at once, not per point
            job = _Job(mechanism, scene, {**values.numbers, **derived}, tuple(names),
                       compiled.key, compiled.meta, compiled.source,
                       {todo[index]: error for index, error in refused.items()})
            blob = _pickled(job, mechanism)     # before any row: workers unpickle it
            bar = _bar(progress, len(points), len(table.rows))
            _load_kernels(compiled, scene)    # once, before any point or worker
            if executor is None and workers is None:
                todo = _run_here(job, todo, table, bar, HERE_SECONDS)
            if todo:
                run_batches(blob, todo, table, executor or workers, bar,
                            _foreign_classes(mechanism))
        rows = [table.rows[point] for point in points]
    default_y = "t_end" if scene.until else next(
        (c for c in columns if c.startswith("peak:")), f"final:{compiled.state_names[-1]}")
    return Sweep(names, columns, rows, default_y, out,
                 _column_units(mechanism, scene, compiled, names))


class Sweep:
    """The rows of a sweep in grid order, with column access and a plot.

    ``sweep[column]`` is an array (floats; strings for ``reason`` and ``error``);
    ``rows`` the dicts; ``failed`` the rows whose simulation failed; ``parameters`` the
    swept names; ``path`` the CSV file (or None); ``units`` the SI unit of each column
    (``""`` where it has none or it is not known), ``label(column)`` ``"P [N]"``.
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

    def __repr__(self):
        return (f"<Sweep over {', '.join(self.parameters)}: {len(self.rows)} points, "
                f"{len(self.failed)} failed>")


# ---------------------------------------------------------------------- the grid
def _grid_points(grid, compiled, max_points, units):
    """Swept names (checked against the scene's parameters) and the grid's points (values
    with a unit checked against the parameter's declared one in ``units``), refused
    before they are built when there are more than ``max_points``."""
    if not grid:
        raise ParameterError("sweep: the grid is empty; give {parameter: [values]}")
    names, axes = [], []
    for key, values in grid.items():
        name = str(key)
        if name not in compiled.param_names:
            raise ParameterError(f"sweep: {name!r} is not a parameter of this scene"
                                 f"{did_you_mean(name, compiled.param_names)} "
                                 f"(parameters: {', '.join(compiled.param_names)})")
        if name in names:
            raise ParameterError(f"sweep: {name} is swept twice")
        if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
            raise ParameterError(f"sweep: the values of {name} must be a list of numbers")
        values = list(dict.fromkeys(to_number(name, v, units.get(name)) for v in values))
        if not values or not all(math.isfinite(v) for v in values):
            raise ParameterError(f"sweep: give {name} at least one value, all finite")
        names.append(name)
        axes.append(values)
    size = math.prod(len(axis) for axis in axes)
    if size > max_points:
        raise SweepError(f"sweep: the grid has {size:,} points "
                             f"({' x '.join(str(len(a)) for a in axes)}), more than "
                             f"max_points = {max_points:,}; raise the limit (max_points=, "
                             "--max-points) if you mean it")
    return names, list(itertools.product(*axes))


def _column_units(mechanism, scene, compiled, names) -> dict:
    """The SI unit of the values of each column."""
    from mechdyn.declare.output_units import output_units
    from mechdyn.units import dimension, si_factor

    def si(unit):
        if not unit or si_factor(unit) == 1:
            return "" if unit == "1" else unit or ""
        return dimension(unit).si
    units = {name: si(mechanism.parameter_units.get(name, "")) for name in names}
    units["t_end"] = "s"
    n = len(compiled.state_names) // 2
    for position, speed in zip(compiled.state_names[:n], compiled.state_names[n:]):
        unit = si(mechanism.units.get(position, "rad"))
        units[f"final:{position}"], units[f"final:{speed}"] = unit, f"{unit}/s"
    for label, unit in output_units(mechanism, scene).items():
        units[f"peak:{label}"] = unit or ""
    return units


def _columns(names, compiled):
    columns = names + ["t_end", "reason"]
    columns += [f"final:{state}" for state in compiled.state_names]
    columns += [f"peak:{label}" for label in compiled.output_labels]
    clash = set(names) & set(columns[len(names):] + ["error"])
    if clash:
        raise ParameterError(f"sweep: parameter {sorted(clash)} clashes with a result column")
    return columns + ["error"]


def _record_of(mechanism, scene, compiled, names, fixed) -> dict:
    """What the rows depend on, as the results file records it."""
    return {"mechdyn": __version__, "mechanism": str(mechanism.name),
            "declaration": compiled.key, "swept": list(names),
            "scene": {"name": str(scene.name), "t_start": repr(scene.t_start),
                      "t_end": repr(scene.t_end), "method": str(scene.method),
                      "rtol": repr(scene.rtol), "atol": repr(scene.atol),
                      "initial": repr(sorted((str(k), str(v))
                                             for k, v in scene.initial.items()))},
            "fixed": fixed}


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
        raise SweepError(
            f"sweep: {', '.join(culprits) or 'the mechanism or scene'} cannot be pickled "
            f"for the sweep's worker processes ({error}); define the element class at "
            "module level in an importable module, not inside a function") from error


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
