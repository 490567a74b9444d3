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

import csv
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import sympy as sp

from .errors import MechdynError
from .stepping import replay
from .symbols import dotted_symbol, is_coordinate

__all__ = ["Result", "Event", "Trajectory"]


@dataclass(frozen=True)
class Event:
    """Something that happened at ``time``: ``kind`` ("stop", "stick", "slip", "end"),
    the element or condition ``name``, and a ``detail`` in words."""
    time: float
    kind: str
    name: str
    detail: str = ""

    def __str__(self):
        return f"t = {self.time:.6g} s: {self.kind} {self.name} ({self.detail})"


class _Segment:
    """Steps of one friction mode: times and states, and how to replay a step for its
    dense output (``method, fun, jac, rtol, atol``)."""

    def __init__(self, t0, y0, signs, stuck, integration):
        self.t, self.y = [t0], [np.array(y0, dtype=float)]
        self.signs, self.stuck = list(signs), list(stuck)
        self.integration = integration
        self._interpolants = {}

    def add(self, t, y):
        self.t.append(t)
        self.y.append(np.array(y, dtype=float))

    def interpolant(self, k):
        """Dense output of step ``k`` (from ``t[k]`` to ``t[k + 1]``), replayed once."""
        if k not in self._interpolants:
            method, fun, jac, rtol, atol = self.integration
            self._interpolants[k] = replay(method, fun, jac, self.t[k], self.y[k],
                                           self.t[k + 1], rtol, atol)
        return self._interpolants[k]


class Trajectory:
    """The integrated motion, segment by segment (a segment per friction mode)."""

    def __init__(self, compiled):
        self.compiled = compiled
        self.segments: list[_Segment] = []

    def start_segment(self, t0, y0, signs, stuck, integration) -> _Segment:
        self.segments.append(_Segment(t0, y0, signs, stuck, integration))
        return self.segments[-1]

    def replace_last_state(self, y):
        """The state after an event's projection replaces the state located there."""
        self.segments[-1].y[-1] = np.array(y, dtype=float)

    def points(self):
        """Times, states and segment index of every step point (boundaries once)."""
        times, states, owner = [], [], []
        for index, segment in enumerate(self.segments):
            start = 1 if index and times and segment.t[0] == times[-1] else 0
            times += segment.t[start:]
            states += segment.y[start:]
            owner += [index] * (len(segment.t) - start)
        if not times:
            return np.zeros(0), np.zeros((2 * self.compiled.dof, 0)), np.zeros(0, int)
        return np.array(times), np.array(states).T, np.array(owner)

    def at(self, times, with_segments=False):
        """States at ``times`` from dense output (shape ``(2n, len)``), and with
        ``with_segments`` the index of the segment (friction mode) of each time."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        out = np.empty((2 * self.compiled.dof, len(times)))
        owners = np.empty(len(times), dtype=int)
        ends = [seg.t[-1] for seg in self.segments]
        first, last = self.segments[0].t[0], self.segments[-1].t[-1]
        for j, value in enumerate(times):
            if not first - 1e-12 * max(1, abs(first)) <= value <= last + 1e-12 * max(1, abs(last)):
                raise MechdynError(f"t = {value} lies outside the simulated interval "
                                   f"[{first}, {last}]")
            owner = next((i for i, end in enumerate(ends) if value <= end), len(ends) - 1)
            segment = self.segments[owner]
            owners[j] = owner
            k = max(min(int(np.searchsorted(segment.t, value, side="left")),
                        len(segment.t) - 1), 1)
            if value == segment.t[k] or len(segment.t) == 1:
                out[:, j] = segment.y[min(k, len(segment.y) - 1)]
            elif value == segment.t[k - 1]:
                out[:, j] = segment.y[k - 1]
            else:
                out[:, j] = segment.interpolant(k - 1)(value)
        return (out, owners) if with_segments else out


class Result:
    """What a simulation computed.

    ``t`` (step times), ``y`` (states, one row per state), ``res[q]``, ``res[md.speed(q)]``,
    ``res[md.acceleration(q)]``, ``res["output"]``; ``final(key)``, ``at(time, key)``;
    ``events``, ``reason`` (why it ended), ``t_end``, ``stats`` (method, steps, nfev,
    njev, nlu, segments, wall_time); ``outputs`` (label -> array at the step points),
    ``outputs_at(times)``; ``energy()``;
    ``to_csv``, ``to_pandas``, ``plot``, ``summary``.
    """

    def __init__(self, compiled, trajectory, events, reason, stats, base_params, scene,
                 mechanism_name, units, run):
        self.compiled, self.trajectory = compiled, trajectory
        self.events, self.reason, self.stats = list(events), reason, stats
        self.scene, self.mechanism_name, self.units = scene, mechanism_name, dict(units)
        self._base, self._run = list(base_params), run
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
        if is_coordinate(key):
            name, order = key.func.__name__, 0
        elif isinstance(key, sp.Derivative) and is_coordinate(key.expr):
            name, order = key.expr.func.__name__, key.variable_count[0][1]
        elif isinstance(key, (str, sp.Symbol)):
            text = str(key)
            if text in self.state_names:
                return ("state", self.state_names.index(text))
            if text in self.compiled.output_labels:
                return ("output", text)
            for i, c in enumerate(self.coordinates):
                if text == str(dotted_symbol(c, 2)):
                    return ("acceleration", i)
            raise KeyError(f"{key!r}: not a state ({', '.join(self.state_names)}) or an output "
                           f"({', '.join(self.compiled.output_labels) or 'none requested'})")
        else:
            label = str(key)
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

    def __getitem__(self, key) -> np.ndarray:
        kind, which = self._index(key)
        if kind == "state":
            return self.y[which]
        if kind == "acceleration":
            return self.accelerations[which]
        return self.outputs[which]

    def final(self, key) -> float:
        """The last value of a coordinate, speed, acceleration or output."""
        return float(self[key][-1])

    def at(self, times, key=None):
        """Dense evaluation at ``times``: a dict of all states, or one state's values."""
        states = self.trajectory.at(times)
        scalar = np.ndim(times) == 0
        if key is None:
            return {name: (row[0] if scalar else row)
                    for name, row in zip(self.state_names, states)}
        kind, which = self._index(key)
        if kind != "state":
            raise KeyError(f"at(): only coordinates and speeds are interpolated, not {key}")
        return states[which][0] if scalar else states[which]

    # ---------------------------------------------------------- derived arrays
    def _each_point(self, evaluate, t=None, y=None, owner=None):
        if t is None:
            t, y, owner = self.t, self.y, self._owner
        return np.array([evaluate(t[j], y[:, j], owner[j]) for j in range(len(t))]).T

    @cached_property
    def accelerations(self) -> np.ndarray:
        """Accelerations at the step points (one row per coordinate)."""
        n = self.compiled.dof

        def evaluate(t, y, owner):
            segment = self.trajectory.segments[owner]
            p = self._base + segment.signs
            if segment.stuck:
                a, _, _ = self._run._constrained(t, y, p, segment.stuck)
                for k in segment.stuck:
                    if self.compiled.frozen[k] >= 0:
                        a[self.compiled.frozen[k]] = 0.0
                return a
            return np.array(self.compiled.rhs(t, y, p))[n:]
        if not len(self.t):
            return np.zeros((n, 0))
        return self._each_point(evaluate).reshape(n, -1)

    @cached_property
    def outputs(self) -> dict:
        """Requested outputs at the step points, by label. A friction element's output is
        the friction force acting (the holding force while stuck)."""
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
        frictions = self.compiled.frictions
        multipliers = getattr(self.compiled, "multiplier_outputs", {})   # closed loops

        def evaluate(t, y, owner):
            segment = self.trajectory.segments[owner]
            p = self._base + segment.signs
            values = list(self.compiled.outputs(t, y, p))
            if multipliers:
                lam = self._run.loop_multipliers(t, y, p, segment.stuck)
                for label, k in multipliers.items():
                    values[labels.index(label)] = lam[k]
            if segment.stuck:
                _, holding, _ = self._run._constrained(t, y, p, segment.stuck)
                for i, label in enumerate(labels):
                    if label in frictions and frictions.index(label) in segment.stuck:
                        values[i] = holding[segment.stuck.index(frictions.index(label))]
            return values
        table = self._each_point(evaluate, times, states, owners)
        return {label: table[i] for i, label in enumerate(labels)}

    def energy(self):
        """Kinetic and potential energy at the step points: ``(T, V)`` arrays."""
        values = np.array([self.compiled.energy(self.t[j], self.y[:, j], self._base
                                                + [0.0] * len(self.compiled.frictions))
                           for j in range(len(self.t))]).T
        return values[0], values[1]

    # ----------------------------------------------------------------- export
    def columns(self) -> dict:
        """All recorded series by column name (time, states, accelerations, outputs)."""
        data = {"t": self.t}
        for i, name in enumerate(self.state_names):
            data[name] = self.y[i]
        for i, c in enumerate(self.coordinates):
            data[str(dotted_symbol(c, 2))] = self.accelerations[i]
        data.update(self.outputs)
        return data

    def to_csv(self, path):
        """Write the step points: one column per series, a header row of names."""
        data = self.columns()
        with open(path, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(list(data))
            for row in zip(*data.values()):
                writer.writerow([repr(float(v)) for v in row])
        return path

    def to_pandas(self):
        """The columns as a ``pandas.DataFrame`` (needs pandas)."""
        try:
            import pandas
        except ImportError:
            raise MechdynError("to_pandas() needs pandas: pip install pandas") from None
        return pandas.DataFrame(self.columns())

    def summary(self) -> str:
        """A few lines: how it ended, final and peak values, events, cost."""
        lines = [f"{self.mechanism_name} — scene {self.scene.name!r}: ended at "
                 f"t = {self.t_end:.6g} s ({self.reason})"]
        n = self.compiled.dof
        for i, c in enumerate(self.coordinates):
            unit = self.units.get(c, "rad")
            final = self.y[i][-1]
            text = f"  {c}: final {final:.6g} {unit}"
            if unit == "rad":
                text += f" = {final / (2 * np.pi):.6g} rev"
            speed = self.y[n + i]
            peak = speed[np.argmax(np.abs(speed))]
            text += f"; speed final {speed[-1]:.6g}, peak {peak:.6g} {unit}/s"
            lines.append(text)
        for label, values in self.outputs.items():
            peak = values[np.argmax(np.abs(values))] if len(values) else float("nan")
            lines.append(f"  {label}: peak {peak:.6g}, final {values[-1]:.6g}")
        for event in self.events:
            lines.append(f"  {event}")
        s = self.stats
        lines.append(f"  {s['method']}: {s['steps']} steps, {s['nfev']} RHS calls, "
                     f"{s.get('njev', 0)} Jacobians, {s.get('wall_time', 0) * 1e3:.1f} ms")
        return "\n".join(lines)

    def __repr__(self):
        return (f"<Result {self.mechanism_name!r} / {self.scene.name!r}: t_end = "
                f"{self.t_end:.6g} s, {len(self.t)} points, {self.reason}>")

    def _repr_html_(self):
        """Jupyter: the summary as a table, the events and the default figure."""
        from .report import result_html
        return result_html(self)

    def plot(self, path=None, points=400):
        """Coordinates, speeds and outputs against time, events marked. Saves to ``path``
        (PNG, SVG, PDF by its suffix) and returns the matplotlib figure."""
        from .plotting import plot_result
        return plot_result(self, path, points)
