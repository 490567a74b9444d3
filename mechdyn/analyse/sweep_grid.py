"""What a sweep computes: its grid of points, what each point yields (a run or a steady
cycle, and the measures taken of it), its columns with their units, and the record that
keys its results file.

A point yields a **run** (``simulate``) unless the sweep measures **steady running**
(:func:`~mechdyn.analyse.fluctuation.steady_running`, one cycle): with ``steady=True``, or
with ``steady=None`` when a measure of steady running (``mean_speed``, ``fluctuation``,
``cycle_time``) is asked for. A run's columns are the swept parameters, the measures
(default: ``t_end``, ``final:STATE`` of every state, ``peak:OUTPUT`` of every output),
``reason`` and ``error``; a steady cycle's the parameters, the measures (default:
``mean_speed``, ``fluctuation``, ``peak:OUTPUT`` over the cycle) and ``error``.

>>> import mechdyn as md
>>> model = md.load_model("models/shoe_brake.py")
>>> plan = Plan.of(model.mechanism, model.scenes["braking"], None, None, 6.28)
>>> plan.cycle, [m.name for m in plan.measures]
(None, ['t_end', 'final:phi', 'final:phidot'])
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

from mechdyn.version import __version__
from mechdyn.errors import ParameterError, did_you_mean
from mechdyn.declare.parameters import to_number
from mechdyn.analyse.measures import MeasureError, STEADY_MEASURES, measure
from mechdyn.analyse.sweep_file import SweepError

__all__ = ["Plan", "grid_points", "record_of"]


@dataclass(frozen=True)
class Plan:
    """What every point yields: ``cycle`` (rad: steady running over it; None: a run),
    ``measures`` (:class:`~mechdyn.analyse.measures.Measure`), ``default_y`` (the
    column a plot shows by default)."""
    cycle: float | None
    measures: tuple
    default_y: str

    @classmethod
    def of(cls, mechanism, scene, measures, steady, cycle, params=None) -> "Plan":
        """The plan for ``measures`` (None: the defaults) and ``steady`` (True, False or
        None: decided by the measures); ``params`` checks a steady scene at once."""
        from mechdyn.compile.compiler import compile_scene
        compiled = compile_scene(mechanism, scene)
        units = _state_units(mechanism, compiled)
        from mechdyn.declare.output_units import output_units
        units.update({k: v or "" for k, v in output_units(mechanism, scene).items()})
        given = None if measures is None else [measure(m, units) for m in measures]
        if steady is None:
            steady = any(m.kind in STEADY_MEASURES for m in given or ())
        if steady:
            _check_steady(mechanism, scene, params, cycle)
        chosen = given if given is not None else [measure(name, units) for name in (
            ["mean_speed", "fluctuation"] if steady else
            ["t_end"] + [f"final:{s}" for s in compiled.state_names]) +
            [f"peak:{label}" for label in compiled.output_labels]]
        _check_measures(chosen, compiled, steady)
        if given:
            default_y = given[0].name
        elif steady:
            default_y = "fluctuation"
        else:
            default_y = "t_end" if scene.until else next(
                (m.name for m in chosen if m.kind == "peak"), chosen[-1].name)
        return cls(float(cycle) if steady else None, tuple(chosen), default_y)

    def columns(self, names) -> list:
        columns = list(names) + [m.name for m in self.measures]
        if self.cycle is None:       # a run's reason: after t_end (where it was), or last
            columns.insert(columns.index("t_end") + 1 if "t_end" in columns[len(names):]
                           else len(columns), "reason")
        clash = set(names) & set(columns[len(names):] + ["error"])
        if clash:
            raise ParameterError(f"sweep: parameter {sorted(clash)} clashes with a result "
                                 "column")
        return columns + ["error"]

    def units(self, mechanism, names) -> dict:
        """The SI unit of the values of each column."""
        units = {name: _si(mechanism.parameter_units.get(name, "")) for name in names}
        units.update({m.name: m.unit for m in self.measures})
        return units

    def record(self) -> dict:
        """What the rows depend on beyond the scene and the values: the measures and
        what they are taken of."""
        return {"measures": [m.key for m in self.measures],
                "outcome": "run" if self.cycle is None else
                f"steady running over a cycle of {self.cycle!r} rad"}


def _si(unit) -> str:
    from mechdyn.units import dimension, si_factor
    if not unit or si_factor(unit) == 1:
        return "" if unit == "1" else unit or ""
    return dimension(unit).si


def _state_units(mechanism, compiled) -> dict:
    n = len(compiled.state_names) // 2
    units = {}
    for position, speed in zip(compiled.state_names[:n], compiled.state_names[n:]):
        unit = _si(mechanism.units.get(position, "rad"))
        units[position], units[speed] = unit, f"{unit}/s"
    return units


def _check_steady(mechanism, scene, params, cycle):
    """Refuse, before any point, a scene steady running cannot take."""
    from mechdyn.analyse.fluctuation import _check
    from mechdyn.analyse.shooting import PeriodicError
    if not (math.isfinite(float(cycle)) and float(cycle) > 0):
        raise PeriodicError(f"sweep: cycle = {cycle} must be positive and finite")
    _check(mechanism, scene, params or {})


def _check_measures(measures, compiled, steady):
    """Every measure can be taken of what the points yield, and its output, element
    or state is recorded by the scene; names are unique."""
    names = [m.name for m in measures]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise MeasureError(f"sweep: measure {', '.join(twice)} asked for twice")
    outcome = "steady" if steady else "run"
    for m in measures:
        if m.of not in ("any", outcome):
            raise MeasureError(
                f"sweep: {m.name} is a measure of {'a run' if m.of == 'run' else 'steady running'}"
                f", but this sweep measures {'steady running' if steady else 'runs'}"
                + (" (steady=True, or a measure of steady running, was asked for)" if steady
                   else " (steady=False)"))
        labels = list(compiled.output_labels)
        if m.kind in ("peak", "rms") and m.argument not in labels:
            raise MeasureError(f"sweep: {m.name}: the scene records no output "
                               f"{m.argument!r}{did_you_mean(m.argument, labels)} (outputs: "
                               f"{', '.join(labels) or 'none'}; add it to outputs=)")
        items = compiled.meta.get("output_items", labels)
        if m.kind == "energy" and f"power:{m.argument}" not in items:
            raise MeasureError(f"sweep: {m.name}: the scene records no power of "
                               f"{m.argument!r}; add 'power:{m.argument}' to its outputs")
        known = list(compiled.state_names) + labels
        if m.kind == "final" and m.argument not in known:
            raise MeasureError(f"sweep: {m.name}: no state or output {m.argument!r}"
                               f"{did_you_mean(m.argument, known)} ({', '.join(known)})")
        if m.kind == "stop_angle" and m.argument and m.argument not in compiled.coordinates:
            raise MeasureError(f"sweep: {m.name}: no coordinate {m.argument!r}"
                               f"{did_you_mean(m.argument, compiled.coordinates)}")


def grid_points(grid, compiled, max_points, units):
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


def record_of(mechanism, scene, compiled, names, fixed, plan) -> dict:
    """What the rows depend on, as the results file records it."""
    return {"mechdyn": __version__, "mechanism": str(mechanism.name),
            "declaration": compiled.key, "swept": list(names),
            "scene": {"name": str(scene.name), "t_start": repr(scene.t_start),
                      "t_end": repr(scene.t_end), "method": str(scene.method),
                      "rtol": repr(scene.rtol), "atol": repr(scene.atol),
                      "initial": repr(sorted((str(k), str(v))
                                             for k, v in scene.initial.items()))},
            "fixed": fixed, **plan.record()}

