"""Results of a simulation: the trajectory, events, outputs, statistics, export and plots.

>>> import mechdyn as md
>>> model = md.load_model("models/rope_hoist.py")
>>> res = model.mechanism.simulate(model.scenes["startup"], model.params)
>>> phi_2 = model.mechanism.coordinates[0]
>>> round(res.final(md.speed(phi_2)), 6)   # 3 + (5.472 t + 24 t^2) / 11.9 at t = 3
22.530756
>>> round(float(res.at(1.0, phi_2)), 6)
3.902185
"""
from __future__ import annotations

from functools import cached_property

import numpy as np

from mechdyn.errors import SimulationError
from mechdyn.simulate.events import Event
from mechdyn.simulate.mode_outputs import run_time_outputs
from mechdyn.simulate.series import SeriesResult
from mechdyn.simulate.trajectory import Trajectory
from mechdyn.tabular import JUPYTER_STYLE, Table, escape

__all__ = ["Result", "Event", "Trajectory"]


class Result(SeriesResult):
    """What a simulation computed.

    ``t`` (step times), ``y`` (states, one row per state), ``res[q]``, ``res[md.speed(q)]``,
    ``res[md.acceleration(q)]``, ``res["output"]``; ``final(key)``, ``at(time, key)``;
    ``events``, ``reason`` (why it ended), ``t_end``, ``stats`` (``method``: the methods
    used, joined by "+"; ``methods``: steps per method; ``switches``: each change of
    method with time, from, to and why; steps, nfev, njev, nlu, segments, wall_time);
    ``outputs`` (label -> array at the step points), ``outputs_at(times)``; ``energy()``;
    ``to_csv``, ``to_pandas``, ``plot``, ``summary``.

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> res = model.mechanism.simulate(model.scenes["braking"], model.params)
    >>> res.reason, round(res.t_end, 9), round(res.final("phi"), 6)
    ('stopped(phi)', 50.0, 2500.0)
    >>> res.at([10.0, 20.0], "phidot").round(9)            # dense output: 100 - 2 t
    array([80., 60.])
    >>> res.stats["method"], res.events[-1].kind
    ('DOP853', 'end')
    """

    def __init__(self, compiled, trajectory, events, reason, stats, base_params, scene,
                 mechanism_name, units, modes):
        self.compiled, self.trajectory = compiled, trajectory
        self.events, self.reason, self.stats = list(events), reason, stats
        self.scene, self.mechanism_name, self.units = scene, mechanism_name, dict(units)
        self._base, self._modes = list(base_params), modes
        self.t, self.y, self._owner = trajectory.points()
        self.state_names = compiled.state_names
        self.coordinates = compiled.coordinates

    # --------------------------------------------------------------- access
    @property
    def t_end(self) -> float:
        """The time the run ended (stop condition, time limit, or failure)."""
        return float(self.t[-1])

    def _index(self, key):
        n = self.compiled.dof
        if isinstance(key, str):
            return self._named(key)
        import sympy as sp                     # a sympy key: the user has sympy loaded
        from mechdyn.symbols import is_coordinate
        if is_coordinate(key):
            name, order = key.func.__name__, 0
        elif isinstance(key, sp.Derivative) and is_coordinate(key.expr):
            name, order = key.expr.func.__name__, key.variable_count[0][1]
        elif isinstance(key, sp.Symbol):
            return self._named(str(key))
        else:
            label = next((name for name, item in self.scene.labelled_outputs()
                          if item == key), str(key))
            if label in self.compiled.output_labels:
                return ("output", label)
            raise KeyError(f"{key!r} is not a coordinate, speed, acceleration or output")
        if name not in self.coordinates:
            eliminated = self.compiled.meta.get("eliminated", {})
            hint = " (made rigid in this scene: eliminated)" if name in eliminated else ""
            raise KeyError(f"{name} is not a coordinate of this result{hint}")
        i = self.coordinates.index(name)
        if order == 0:
            return ("state", i)
        if order == 1:
            return ("state", n + i)
        return ("acceleration", i)

    def _named(self, text):
        if text in self.state_names:
            return ("state", self.state_names.index(text))
        if text in self.compiled.output_labels:
            return ("output", text)
        if text in self.acceleration_names:
            return ("acceleration", self.acceleration_names.index(text))
        raise KeyError(f"{text!r}: not a state ({', '.join(self.state_names)}) or an output "
                       f"({', '.join(self.compiled.output_labels) or 'none requested'})")

    @property
    def acceleration_names(self) -> list:
        """The names of the accelerations (``phiddot``), as columns name them."""
        return self.compiled.meta["acceleration_names"]

    def __getitem__(self, key) -> np.ndarray:
        kind, which = self._index(key)
        if kind == "state":
            return self.y[which]
        if kind == "acceleration":
            return self.accelerations[which]
        return self.outputs[which]

    def _state_row(self, key) -> int:
        kind, which = self._index(key)
        if kind != "state":
            raise KeyError(f"at(): only coordinates and speeds are interpolated, not {key}")
        return which

    # ---------------------------------------------------------- derived arrays
    def _each_point(self, evaluate, t=None, y=None, owner=None):
        if t is None:
            t, y, owner = self.t, self.y, self._owner
        return np.array([evaluate(t[j], y[:, j], owner[j]) for j in range(len(t))]).T

    @cached_property
    def accelerations(self) -> np.ndarray:
        """Accelerations at the step points (one row per coordinate)."""
        return self._accelerations(self.t, self.y, self._owner)

    def accelerations_at(self, times) -> np.ndarray:
        """Accelerations at any ``times`` inside the run, from the dense output."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        states, owners = self.trajectory.at(times, with_segments=True)
        return self._accelerations(times, states, owners)

    def _accelerations(self, times, states, owners) -> np.ndarray:
        n = self.compiled.dof

        def evaluate(t, y, owner):
            mode = self.trajectory.segments[owner].mode
            if mode.groups or self._modes.gears:        # constrained, or a gear's loss
                return self._modes.accelerations(t, y, mode)[0]
            return np.array(self.compiled.rhs(t, y, self._modes.p(mode)))[n:]
        if not len(times):
            return np.zeros((n, 0))
        return self._each_point(evaluate, times, states, owners).reshape(n, -1)

    @cached_property
    def outputs(self) -> dict:
        """Requested outputs at the step points, by label (a partial result's are NaN
        where they have no real value: past the edge of a root's domain). A friction element's output is
        the friction force acting (the holding force while stuck), a stop's its contact
        force, a lossy gear's its mesh moment (the moment its input passes into it)."""
        return self._outputs(self.t, self.y, self._owner)

    def outputs_at(self, times) -> dict:
        """Requested outputs at any ``times`` inside the run, from the dense output."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        states, owners = self.trajectory.at(times, with_segments=True)
        return self._outputs(times, states, owners)

    def _outputs(self, times, states, owners) -> dict:
        labels = self.compiled.output_labels
        if not labels or not len(times):
            return {label: np.zeros(len(times)) for label in labels}
        multipliers = self.compiled.multiplier_outputs          # closed loops
        items = self.compiled.meta.get("output_items", labels)

        def evaluate(t, y, owner):
            mode = self.trajectory.segments[owner].mode
            try:
                values = list(self.compiled.outputs(t, y, self._modes.p(mode)))
            except (ArithmeticError, ValueError) as error:
                if self.reason.startswith("failed"):    # a partial result, at its end
                    return [float("nan")] * len(labels)
                raise SimulationError(f"{self._outside(t, y, mode) or 'an output'} cannot be "
                                      f"evaluated at t = {t:.6g} s ({type(error).__name__}: "
                                      f"{error})", partial=self) from None
            if multipliers:
                lam = self._modes.multipliers(t, y, mode)
                for label, k in multipliers.items():
                    values[labels.index(label)] = lam[k]
            return run_time_outputs(self._modes, t, y, mode, items, values)
        table = self._each_point(evaluate, times, states, owners)
        return {label: table[i] for i, label in enumerate(labels)}

    def _outside(self, t, y, mode) -> str:
        """The outputs whose root, power, logarithm or arcsine has no real value at
        ``(t, y)``."""
        values = self.compiled.events(t, y, self._modes.p(mode))
        return ", ".join(label for (kind, label), value in zip(self.compiled.event_kinds,
                                                                values)
                         if kind == "domain" and label.startswith("output ") and value < 0)

    def energy(self):
        """Kinetic and potential energy at the step points: ``(T, V)`` arrays."""
        def evaluate(t, y, owner):          # the mode's vector: switch flags included
            return self.compiled.energy(t, y, self._modes.p(self.trajectory.segments[owner].mode))
        values = self._each_point(evaluate).reshape(2, -1)
        return values[0], values[1]

    # ----------------------------------------------------------------- export
    def columns(self, sample=None) -> dict:
        """All recorded series by column name (time, states, accelerations, outputs):
        at the step points, or every ``sample`` seconds from the start (dense output)."""
        if sample is None:
            t, y, accelerations, outputs = self.t, self.y, self.accelerations, self.outputs
        else:
            t = self.sample_times(sample)
            y, accelerations = self.trajectory.at(t), self.accelerations_at(t)
            outputs = self.outputs_at(t)
        data = {"t": t}
        for i, name in enumerate(self.state_names):
            data[name] = y[i]
        for i, name in enumerate(self.acceleration_names):
            data[name] = accelerations[i]
        data.update(outputs)
        return data

    @property
    def output_labels(self) -> list:
        """The labels of the requested outputs."""
        return list(self.compiled.output_labels)

    def peak(self, key, samples=8) -> tuple:
        """``(time, value)`` of the largest magnitude of a state or output over the run,
        from the dense output: ``samples`` points in every step, then the best one
        refined between its neighbours (a peak between two steps is found)."""
        kind, which = self._index(key)
        if kind == "acceleration":
            raise KeyError(f"peak(): {key} is an acceleration; ask for a state or output")
        if len(self.t) < 2:
            value = self[key]
            return float(self.t[-1]), float(value[-1])
        per_step = max(1, min(samples, 20_000 // max(len(self.t) - 1, 1)))
        fractions = np.arange(per_step) / per_step
        times = np.append((self.t[:-1, None] + np.diff(self.t)[:, None] * fractions).ravel(),
                          self.t[-1])

        def values(at):
            if kind == "state":
                return self.trajectory.at(at)[which]
            return self.outputs_at(at)[which]
        sampled = np.abs(values(times))
        finite = np.isfinite(sampled)        # a partial result's outputs may end in NaN
        best = int(np.argmax(np.where(finite, sampled, -1.0))) if finite.any() else -1
        best %= len(times)
        low, high = times[max(best - 1, 0)], times[min(best + 1, len(times) - 1)]
        if high > low:
            from scipy.optimize import minimize_scalar
            found = minimize_scalar(lambda x: -abs(float(values(np.array([x]))[0])),
                                    bounds=(low, high), method="bounded",
                                    options={"xatol": 1e-12 * max(1.0, abs(high))})
            if -found.fun > sampled[best]:
                return float(found.x), float(values(np.array([found.x]))[0])
        return float(times[best]), float(values(times[best:best + 1])[0])

    def summary(self, units=None) -> str:
        """A few lines: how it ended, final and peak values, events, cost. ``units``
        shows columns in other units (``{"speed": "rpm", "power": "kW"}``)."""
        from mechdyn.display import Display, column_units, cost_line, event_groups, tidy
        shown, si = Display(units), column_units(self)
        shown.check(si)
        lines = [f"{self.mechanism_name} — scene {self.scene.name!r}: ended at "
                 f"t = {self.t_end:.6g} s ({self.reason})"]
        n = self.compiled.dof
        for i, c in enumerate(self.coordinates):
            (final,), unit = shown.values(c, si[c], tidy(self.y[i][-1:], np.max(
                np.abs(self.y[i]))))
            text = f"  {c}: final {final:.6g} {unit}"
            if unit == "rad":
                text += f" = {final / (2 * np.pi):.6g} rev"
            name = self.state_names[n + i]
            speed, speed_unit = shown.values(name, si[name], tidy(
                [self.y[n + i][-1], self.peak(name)[1]]))
            text += f"; speed final {speed[0]:.6g}, peak {speed[1]:.6g} {speed_unit}"
            lines.append(text)
        for label, values in self.outputs.items():
            values, unit = shown.values(label, si[label],
                                        tidy([values[-1], self.peak(label)[1]]))
            unit = f" {unit}" if unit else ""                # once, after both
            lines.append(f"  {label}: peak {values[1]:.6g}, final {values[0]:.6g}{unit}")
        lines += [f"  {text}" for text, _, _ in event_groups(self.events, self.t[0],
                                                              self.t_end)]
        lines.append(f"  {cost_line(self.stats)}")
        return "\n".join(lines)

    def __repr__(self):
        return (f"<Result {self.mechanism_name!r} / {self.scene.name!r}: t_end = "
                f"{self.t_end:.6g} s, {len(self.t)} points, {self.reason}>")

    def values_table(self) -> Table:
        """Start, final and peak (largest magnitude, between steps too) of every
        coordinate, speed and output, with its SI unit."""
        from mechdyn.plotting import dense_series
        n = self.compiled.dof
        _, states, outputs = dense_series(self)
        rows = []
        for i, name in enumerate(self.coordinates):
            unit = self.units.get(name, "rad")
            rows += [_value_row(name, states[i], unit),
                     _value_row(f"d{name}/dt", states[n + i], f"{unit}/s")]
        rows += [_value_row(label, values, self.units.get(label, ""))
                 for label, values in outputs.items()]
        return Table(["quantity", "start", "final", "peak", "unit"], rows)

    def events_table(self) -> Table:
        """The events: time, kind, element or condition, detail."""
        return Table(["t [s]", "event", "element or condition", "detail"],
                     [[float(e.time), e.kind, e.name, e.detail] for e in self.events])

    def html(self) -> str:
        """How it ended, the values and events tables, the cost and the default figure."""
        from mechdyn.plotting import figure_html
        s = self.stats
        return "".join([
            f"<p>Ended at t = {self.t_end:.6g} s ({escape(self.reason)}).</p>",
            self.values_table().html(),
            self.events_table().html() if self.events else "",
            f"<p class='note'>{escape(s['method'])}: {s['steps']} steps, {s['nfev']} "
            f"right-hand-side calls, {s.get('njev', 0)} Jacobians, "
            f"{s.get('wall_time', 0) * 1e3:.1f} ms</p>",
            figure_html(self.plot(), "the scene's default figure")])

    def _repr_html_(self):
        """Jupyter: the summary as a table, the events and the default figure."""
        return (f"<div class='mechdyn'>{JUPYTER_STYLE}<h3>{escape(self.mechanism_name)} — "
                f"scene {escape(self.scene.name)}</h3>{self.html()}</div>")

    def plot(self, path=None, points=400, sample=None, units=None):
        """Coordinates, speeds and outputs against time, events marked, axes labelled
        with units (``units`` shows other ones, ``{"speed": "rpm"}``). Curves at
        ``points`` even times and the steps, or every ``sample`` seconds. Saves to
        ``path`` (PNG, SVG, PDF by its suffix) and returns the matplotlib figure."""
        from mechdyn.plotting import plot_result
        return plot_result(self, path, points, sample=sample, units=units)


def _value_row(label, values, unit) -> list:
    finite = values[np.isfinite(values)]          # a partial result's end may have none
    peak = finite[abs(finite).argmax()] if len(finite) else float("nan")
    return [label, float(values[0]), float(values[-1]), float(peak), unit]
