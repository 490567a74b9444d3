"""The result of a duty cycle (:func:`mechdyn.analyse.cycle.duty_cycle`): its phases one after
another in cycle time, with the energy and the peaks of each.

Arrays at step points (``t``, ``y``, ``res[key]``, ``outputs``) run through the phases
in turn; a phase boundary appears twice, as the end of one phase and the start of the
next (the same state; outputs and accelerations may jump, the effects change). Dense
evaluations (``at``, ``outputs_at``, ``columns(sample=...)``) take the later phase at a
boundary. An output a phase does not record is NaN there. ``phases[k].result`` is the
phase's own :class:`~mechdyn.simulate.result.Result`, on its scene's clock (cycle time minus the
phase's ``offset``).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from mechdyn.errors import MechdynError
from mechdyn.simulate.events import Event
from mechdyn.simulate.series import SeriesResult

__all__ = ["CycleResult", "Phase", "PhaseEnergy"]


@dataclass(frozen=True)
class PhaseEnergy:
    """Energy over a phase: kinetic and potential energy ``(start, end)`` and the work
    of each load, friction and damper (J); ``residual`` is the balance
    ``delta T + delta V - sum(work)``, zero up to the integration error."""
    kinetic: tuple
    potential: tuple
    work: dict

    @property
    def residual(self) -> float:
        change = (self.kinetic[1] - self.kinetic[0]) + (self.potential[1] - self.potential[0])
        return change - sum(self.work.values())

    def __str__(self):
        from mechdyn.display import tidy
        every = [*self.kinetic, *self.potential, *self.work.values()]
        scale = max(abs(value) for value in every)       # a value within rounding: 0
        t0, t1, v0, v1, *works = tidy(every, scale).tolist()
        work = ", ".join(f"{name} {_joules(value, sign=True)}" for name, value in
                         zip(self.work, works)) or "none"
        return (f"T {_joules(t0)} -> {_joules(t1)}, V {_joules(v0)} -> {_joules(v1)}; "
                f"work: {work} (balance {self.residual:.2g} J)")


class Phase:
    """One phase of a duty cycle: ``number`` (from 1), ``name``, the user's ``scene``,
    its ``result`` (on the scene's clock), ``offset`` (cycle time minus scene time),
    ``start``, ``end`` (cycle time), ``reason``; ``peak(key)``, ``energy``."""

    def __init__(self, number, name, scene, result, offset, powers):
        self.number, self.name, self.scene, self.result = number, name, scene, result
        self.offset, self.powers = float(offset), dict(powers)
        self.start = self.offset + float(result.t[0])
        self.end = self.offset + result.t_end
        self.reason = result.reason
        hidden = set(powers.values()) - {label for label, _ in scene.labelled_outputs()}
        self.output_labels = [label for label in result.output_labels if label not in hidden]

    def peak(self, key) -> tuple:
        """``(cycle time, value)`` of the largest magnitude of a state or output."""
        time, value = self.result.peak(key)
        return time + self.offset, value

    @cached_property
    def energy(self) -> PhaseEnergy:
        """Kinetic and potential energy at the start and end, work of each element
        (its power integrated by 4-point Gauss-Legendre over every step)."""
        kinetic, potential = self.result.energy()
        t = self.result.t
        work = dict.fromkeys(self.powers, 0.0)
        if len(t) > 1 and self.powers:
            x, w = np.polynomial.legendre.leggauss(4)
            h = np.diff(t)
            nodes = (t[:-1, None] + (x[None, :] + 1) / 2 * h[:, None]).ravel()
            values = self.result.outputs_at(nodes)
            for name, label in self.powers.items():
                work[name] = float(np.sum(values[label].reshape(-1, 4) @ w * h / 2))
        return PhaseEnergy((float(kinetic[0]), float(kinetic[-1])),
                           (float(potential[0]), float(potential[-1])), work)

    def __repr__(self):
        return (f"<Phase {self.number} {self.name!r}: t = {self.start:.6g} ... "
                f"{self.end:.6g} s, {self.reason}>")


class CycleResult(SeriesResult):
    """What a duty cycle computed (see the module): ``phases``, ``phase(key)``, ``t``,
    ``y``, ``res[key]``, ``final(key)``, ``at(times, key)``, ``outputs``,
    ``outputs_at(times)``, ``accelerations_at(times)``, ``events`` (cycle time),
    ``reason``, ``t_end``, ``stats``, ``units``, ``columns(sample)``, ``to_csv``,
    ``to_pandas``, ``plot``, ``summary``.

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> phi = model.mechanism.coordinates[0]
    >>> coast = md.Scene("coast", effects=[], initial={phi: 0, md.speed(phi): 100}, t_end=1)
    >>> cycle = md.duty_cycle(model, [coast, "braking"])
    >>> round(cycle.t_end, 9), cycle.reason
    (51.0, 'stopped(phi)')
    >>> cycle.at([0.5, 11.0], "phidot").round(9)           # coasting, then 10 s braked
    array([100.,  80.])
    """

    def __init__(self, mechanism_name, phases):
        self.mechanism_name, self.phases = mechanism_name, list(phases)
        first = self.phases[0].result
        self.state_names, self.coordinates = first.state_names, first.coordinates
        self.acceleration_names = first.acceleration_names
        self.t = np.concatenate([p.result.t + p.offset for p in self.phases])
        self.y = np.hstack([p.result.y for p in self.phases])
        self.output_labels = list(dict.fromkeys(label for p in self.phases
                                                for label in p.output_labels))
        self.units = {}
        for p in self.phases:
            self.units.update({k: v for k, v in p.result.units.items()
                               if k in self.output_labels or k in self.coordinates})
        self.events = [Event(e.time + p.offset, e.kind, e.name, e.detail)
                       for p in self.phases for e in p.result.events]
        self.reason = self.phases[-1].reason
        self.name = "+".join(p.name for p in self.phases)
        self._starts = np.array([p.start for p in self.phases])
        self.trajectory = _Timeline(self)

    @property
    def t_end(self) -> float:
        return float(self.t[-1])

    def phase(self, key) -> Phase:
        """A phase by number (from 1) or name."""
        for p in self.phases:
            if key == p.number if isinstance(key, int) else key == p.name:
                return p
        raise KeyError(f"no phase {key!r}: phases {', '.join(p.name for p in self.phases)}")

    @property
    def stats(self) -> dict:
        """Solver statistics summed over the phases; ``phases``: each phase's own."""
        each = [p.result.stats for p in self.phases]
        total = {key: sum(s.get(key, 0) for s in each)
                 for key in ("steps", "nfev", "njev", "nlu", "segments", "wall_time")}
        methods = dict.fromkeys(m for s in each for m in s["method"].split("+") if m)
        total.update(method="+".join(methods), phases=each)
        return total

    # --------------------------------------------------------------- access
    def __getitem__(self, key) -> np.ndarray:
        parts = []
        for p in self.phases:
            try:
                parts.append(p.result[key])
            except KeyError:
                if str(key) not in self.output_labels:
                    raise
                parts.append(np.full(len(p.result.t), np.nan))
        return np.concatenate(parts)

    @cached_property
    def outputs(self) -> dict:
        """The outputs at the step points by label (NaN in phases without them)."""
        return {label: self[label] for label in self.output_labels}

    def _by_phase(self, times, evaluate, rows):
        """``evaluate(phase, local_times)`` (an array ``(rows, k)``) over the phases the
        ``times`` fall in; ``(rows, len(times))``."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        slack = 1e-12 * max(1.0, abs(self.t[0]), abs(self.t[-1]))
        outside = (times < self.t[0] - slack) | (times > self.t[-1] + slack)
        if np.any(outside):
            raise MechdynError(f"t = {times[outside][0]} lies outside the duty cycle "
                               f"[{self.t[0]}, {self.t[-1]}]")
        which = np.clip(np.searchsorted(self._starts, times, side="right") - 1, 0,
                        len(self.phases) - 1)
        out = np.full((rows, len(times)), np.nan)
        for k in np.unique(which):
            mask = which == k
            phase = self.phases[k]
            local = np.clip(times[mask] - phase.offset, phase.result.t[0], phase.result.t[-1])
            out[:, mask] = evaluate(phase, local)
        return out

    def _state_row(self, key) -> int:
        return self.state_names.index(_state_name(key, self.state_names))

    def outputs_at(self, times) -> dict:
        """Outputs at cycle ``times`` from the dense output (NaN where not recorded)."""
        labels = self.output_labels

        def evaluate(phase, local):
            values = phase.result.outputs_at(local)
            return np.array([values.get(label, np.full(len(local), np.nan))
                             for label in labels]).reshape(len(labels), -1)
        table = self._by_phase(times, evaluate, len(labels))
        return {label: table[i] for i, label in enumerate(labels)}

    def accelerations_at(self, times) -> np.ndarray:
        """Accelerations at cycle ``times`` (one row per coordinate)."""
        return self._by_phase(times, lambda phase, local: phase.result.accelerations_at(local),
                              len(self.coordinates))

    def phase_at(self, times) -> np.ndarray:
        """The phase name at each of ``times`` (the later phase at a boundary)."""
        names = np.array([p.name for p in self.phases], dtype=object)
        index = self._by_phase(times, lambda p, local: np.full(len(local), p.number - 1), 1)
        return names[index[0].astype(int)]

    def energy(self):
        """Kinetic and potential energy at the step points: ``(T, V)`` arrays."""
        parts = [p.result.energy() for p in self.phases]
        return np.concatenate([T for T, _ in parts]), np.concatenate([V for _, V in parts])

    # ----------------------------------------------------------------- export
    def columns(self, sample=None) -> dict:
        """All series by column: ``t``, ``phase`` (its name), states, accelerations,
        outputs; at the step points, or every ``sample`` seconds of cycle time."""
        accelerations = list(self.acceleration_names)
        if sample is None:
            t, phase = self.t, np.concatenate([[p.name] * len(p.result.t)
                                               for p in self.phases]).astype(object)
            y = self.y
            acc = np.hstack([p.result.accelerations for p in self.phases])
            outputs = self.outputs
        else:
            t = self.sample_times(sample)
            phase, y = self.phase_at(t), self.trajectory.at(t)
            acc, outputs = self.accelerations_at(t), self.outputs_at(t)
        data = {"t": t, "phase": phase}
        data.update(zip(self.state_names, y))
        data.update(zip(accelerations, acc))
        data.update(outputs)
        return data

    def plot(self, path=None, points=400, sample=None, units=None):
        """One figure of the whole cycle (as :meth:`mechdyn.simulate.result.Result.plot`), the
        phases shaded in turn, their boundaries marked and named."""
        from mechdyn.plotting import plot_result
        return plot_result(self, path, points, sample=sample, units=units,
                           phases=[(p.name, p.start, p.end) for p in self.phases],
                           title=f"{self.mechanism_name} — duty cycle {self.name} "
                           f"({self.reason})")

    def __repr__(self):
        return (f"<CycleResult {self.mechanism_name!r} / {self.name}: t_end = "
                f"{self.t_end:.6g} s, {len(self.phases)} phases, {self.reason}>")

    def summary(self, units=None) -> str:
        """Per phase: time span and why it ended, each coordinate's travel, speed at
        start and end and peak, each output's peak and end value, the energy (T, V and
        the work of each element), the events; then the cost."""
        from mechdyn.display import Display, column_units, cost_line, tidy
        shown, si = Display(units), column_units(self)
        shown.check(si)
        n = len(self.coordinates)
        scale = {key: np.max(np.abs(self[key])) for key in self.state_names}
        lines = [f"{self.mechanism_name} — duty cycle {self.name}: {len(self.phases)} "
                 f"phases, t = {self.t[0]:.6g} ... {self.t_end:.6g} s ({self.reason})"]
        for p in self.phases:
            r = p.result
            lines.append(f"  phase {p.number} {p.name!r}: t = {p.start:.6g} ... "
                         f"{p.end:.6g} s ({p.reason})")
            for i, c in enumerate(self.coordinates):
                (a, b), unit = shown.values(c, si[c], tidy(r.y[i][[0, -1]], scale[c]))
                speed = self.state_names[n + i]
                values, speed_unit = shown.values(speed, si[speed], tidy(
                    [r.y[n + i][0], r.y[n + i][-1], p.peak(speed)[1]], scale[speed]))
                lines.append(f"    {c}: {a:.6g} -> {b:.6g} {unit}; speed {values[0]:.6g} "
                             f"-> {values[1]:.6g}, peak {values[2]:.6g} {speed_unit}")
            for label in p.output_labels:
                values, unit = shown.values(label, si.get(label, ""), tidy(
                    [p.peak(label)[1], r.outputs[label][-1]]))
                unit = f" {unit}" if unit else ""
                lines.append(f"    {label}: peak {values[0]:.6g}{unit}, end "
                             f"{values[1]:.6g}{unit}")
            lines.append(f"    energy: {p.energy}")
            for e in r.events:
                lines.append(f"    {Event(e.time + p.offset, e.kind, e.name, e.detail)}")
        lines.append(f"  {cost_line(self.stats)}")
        return "\n".join(lines)

    def __repr__(self):
        return (f"<CycleResult {self.mechanism_name!r} / {self.name}: t_end = "
                f"{self.t_end:.6g} s, {len(self.phases)} phases, {self.reason}>")


class _Timeline:
    """The states of the whole cycle at any times (what plots read as a trajectory)."""

    def __init__(self, cycle):
        self.cycle = cycle

    def at(self, times):
        cycle = self.cycle
        return cycle._by_phase(times, lambda phase, local: phase.result.trajectory.at(local),
                               len(cycle.state_names))


def _state_name(key, state_names) -> str:
    from mechdyn.symbols import is_coordinate, plain
    import sympy as sp
    if is_coordinate(key) or isinstance(key, sp.Derivative):
        key = str(plain(key))
    if str(key) not in state_names:
        raise KeyError(f"at(): {key!r} is not a state ({', '.join(state_names)})")
    return str(key)


def _joules(value, sign=False) -> str:
    size = abs(value)
    scale, unit = (1e6, "MJ") if size >= 1e6 else (1e3, "kJ") if size >= 1e3 else (1, "J")
    return f"{value / scale:{'+' if sign else ''}.5g} {unit}"
