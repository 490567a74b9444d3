"""The simulation driver: a run as a sequence of segments.

A segment is integrated with one friction mode and one method; it ends at an event (a
stop condition, a friction element sticking, releasing or engaging, a stop's limit
reached: an impact, :mod:`mechdyn.contacts`; a switch of a ``Piecewise``), when the
explicit method turns out to be held by stability (stiffness),
or when its method fails. The driver then decides what comes next: the new friction mode
(:mod:`mechdyn.friction`), the method of the next segment (:mod:`mechdyn.methods`: the
stiffness is measured again at every segment start), or another method from the last
accepted state after a failure. ``stats["switches"]`` records every change of method
(time, from, to, why).

Budgets bound the work: a run that exceeds its steps or its wall time stops with a
:class:`~mechdyn.errors.SimulationError` naming the scene, the time reached, the step size
and the method, and what to try; like every failure it carries the result computed so far
(``error.partial``). ``progress(t, t_end)`` is called about every quarter second.
"""
from __future__ import annotations

import math
import time

import numpy as np

from .compile import SingularMassError
from .contacts import jump
from .errors import SimulationError
from .events import Event, EventWatch
from .friction import FrictionModes, Mode
from .methods import (STIFF, StiffnessMonitor, choose_method, explicit_for, fallbacks,
                      motion_jacobian, segment_tolerances)
from .result import Result
from .stepping import EXPLICIT, WITH_JACOBIAN, ScipySegment
from .loop_watch import LoopWatch
from .trajectory import Segment, Trajectory

__all__ = ["Budget", "Driver"]

_CHUNK = 200                 # steps between progress reports and budget checks
_SAME_INSTANT = 1e-12        # relative time under which events count as simultaneous
_EVENT_LOOP_LIMIT = 200      # events at one instant before the run is called stuck
_COLLAPSE = 1e-12            # a step shorter than this fraction of the run has collapsed
_PROGRESS = 1e-6             # a segment this much of the rest long clears past failures


class Budget:
    """Limits of a run's work: ``max_steps`` accepted steps and ``max_wall_time``
    seconds (None: unbounded)."""

    def __init__(self, max_steps=None, max_wall_time=None):
        self.max_steps, self.max_wall_time = max_steps, max_wall_time


class Driver:
    """Runs one scene: ``Driver(compiled, base, scene, method, atol, ...).run(y0)``.

    ``method`` is a solver name or ``"auto"``; ``base`` the parameter values."""

    def __init__(self, compiled, base, scene, method, atol, mechanism, budget=None,
                 progress=None):
        self.c, self.base, self.scene, self.atol = compiled, list(base), scene, atol
        self.auto = method == "auto"
        self.method = method
        self.modes = FrictionModes(compiled, base, scene.time_limit - scene.t_start)
        self.mechanism_name, self.units = mechanism.name, mechanism.units
        self.budget = budget or Budget()
        self.progress = progress
        self.n = compiled.dof
        self.trajectory = Trajectory()
        self.events: list[Event] = []
        self.stats = {"method": "", "methods": {}, "steps": 0, "nfev": 0, "njev": 0,
                      "nlu": 0, "segments": 0, "switches": [], "wall_time": 0.0}
        kinds = compiled.event_kinds
        self.stop_index = [i for i, (kind, _) in enumerate(kinds) if kind == "stop"]
        self.switch_index = [i for i, (kind, _) in enumerate(kinds) if kind == "switch"]
        self.stop_directions = [c.direction for c in scene.until]
        self.max_step = self._max_step(compiled)
        self.loops = LoopWatch(compiled, scene.rtol)

    # ------------------------------------------------------------------ the run
    def run(self, y0) -> Result:
        t, t_end = self.scene.t_start, self.scene.time_limit
        y = np.array(y0, dtype=float)
        self.started = time.perf_counter()
        self.last_report = self.started
        reason = "t_end"
        try:
            self._check_mass(t, y)
            muted, instant, count = set(), None, 0
            y, touching, resting = jump(self.modes, t, y, None, (), self.events)
            mode = self.modes.decide(t, y, self._flags(t, y, Mode(), muted),
                                     at_rest=resting, events=self.events, touching=touching)
            y = self.modes.project(t, y, mode)
            method, why = self._choose(mode, t, y)
            h = None
            self._failed = []
            while t < t_end:
                t_before = t
                outcome, h = self._segment(mode, method, why, t, y, t_end, h, muted)
                t, y = outcome.t, outcome.y
                if outcome.status != "failed" and t - t_before > _PROGRESS * (t_end - t_before):
                    self._failed = []
                if outcome.status == "finished":
                    break
                if outcome.status == "drift":          # closed loops: back onto them
                    y = self.modes.project(t, y, mode)
                    self.stats["projections"] = self.stats.get("projections", 0) + 1
                    continue
                if outcome.status == "stiff":
                    if method in EXPLICIT:
                        method, why = self._switch(t, method, STIFF, "the explicit method "
                                                   "is held at its stability limit (stiff)")
                    else:
                        method, why = self._switch(
                            t, method, explicit_for(self.scene.rtol), "the stiff method's "
                            "steps stay within the explicit method's stability (not stiff)")
                    continue
                if outcome.status == "failed":
                    method, why = self._after_failure(t, y, mode, method, outcome.message)
                    h = None
                    continue
                count = count + 1 if instant is not None and \
                    t - instant <= _SAME_INSTANT * max(1.0, abs(t)) else 1
                instant = t
                if count > _EVENT_LOOP_LIMIT:
                    raise SimulationError(f"integration failed at t = {t:.6g} s: "
                                          f"{count} events at the same instant (the modes "
                                          "cannot settle)")
                stop, mode, y, muted = self._after_event(t, y, mode, outcome.fired, muted)
                if stop is not None:
                    reason = stop
                    break
                if self.auto:
                    method, why = self._choose(mode, t, y)
                h = None
        except SimulationError as error:
            self._finish()
            error.partial = self._result("failed: " + str(error))
            if not str(error).startswith("integration"):
                error.args = (f"integration failed: {error}",)
            raise
        if reason == "t_end" and self.c.stop_labels:
            reason = "t_end (stop condition not reached)"
        self._finish()
        return self._result(reason)

    def _finish(self):
        self.stats["wall_time"] = time.perf_counter() - self.started
        used = self.stats["methods"]
        self.stats["method"] = "+".join(used) if used else self.method

    # ------------------------------------------------------------- a segment
    def _segment(self, mode, method, why, t0, y0, t_end, h, muted):
        """Integrate from ``(t0, y0)`` until something happens; returns the outcome and
        the last step size."""
        p = self.modes.p(mode)
        constrained = self.modes.rhs(mode)          # stuck elements or a gear's loss
        fun = constrained or _fast_rhs(self.c.raw["rhs"], p, 2 * self.n)
        jac = None
        if method in WITH_JACOBIAN and constrained is None:
            jac = _tolerant(lambda t, y: self.c.jac(t, y, p), (2 * self.n, 2 * self.n))
        fun = _tolerant(fun, (2 * self.n,))
        watch = self._watch(mode, p, t0, y0, muted)
        monitor = None
        if self.auto and method in EXPLICIT | {STIFF} and not mode.groups:
            monitor = StiffnessMonitor(method, lambda t, y: motion_jacobian(self.c, t, y, p),
                                       self.scene.rtol)
        rtol, atol = self.scene.rtol, self.atol
        if self.auto:
            rtol, atol = segment_tolerances(method, rtol, atol)
        segment = self.trajectory.add(Segment(t0, y0, mode, method))
        self.stats["segments"] += 1
        max_step = self.max_step if mode.groups else np.inf
        span = self.scene.time_limit - self.scene.t_start
        run = ScipySegment(method, fun, jac, t0, y0, t_end, rtol, atol,
                           segment, watch, monitor, first_step=h, max_step=max_step,
                           min_step=_COLLAPSE * span, drift=self.loops.drifted(y0, p))
        counted = dict.fromkeys(("steps", "nfev", "njev", "nlu"), 0)
        while True:
            outcome = run.advance(_CHUNK)
            self.trajectory.changed()
            counts = run.counts
            for key in counted:
                self.stats[key] += counts[key] - counted[key]
            self.stats["methods"][method] = self.stats["methods"].get(method, 0) \
                + counts["steps"] - counted["steps"]
            counted = counts
            self._check_budget(outcome.t, run.h, method)
            self._report(outcome.t, t_end)
            if outcome.status == "chunk":
                continue
            if outcome.status in ("event", "finished", "stiff", "drift"):
                self._check_finite(outcome.t, outcome.y)
            return outcome, run.h

    def _watch(self, mode, p, t0, y0, muted):
        """The events of a segment: stop conditions, switching functions (except those
        muted for chattering: unlocked) and the friction events of the mode. A switching
        function is watched from the side its flag locks, so a flag that is wrong at the
        start fires at once."""
        friction = self.modes.watched(mode, t0, y0)
        compiled_events = self.c.raw["events"]
        size = len(self.c.event_kinds)
        chosen = self.stop_index + [i for i in self.switch_index if i not in muted]
        directions = self.stop_directions + [0] * (len(chosen) - len(self.stop_index))
        zero_before = [False] * len(chosen)
        directions += [direction for _, _, direction, _ in friction]
        zero_before += [True] * len(friction)
        minor = self.loops.watched_minor(t0, y0, p)        # closed loops' singularity
        if minor is not None:
            directions.append(minor[1])
            zero_before.append(False)
        self._watch_map = [("compiled", i) for i in chosen] + \
            [("friction", j) for j in range(len(friction))] + \
            ([("minor", minor[0])] if minor is not None else [])
        self._friction_watched = friction
        if not directions:
            return None

        def values(t, y):
            out = [0.0] * size
            compiled_events(t, _floats(y), p, out)
            chosen_values = [out[i] for i in chosen]
            chosen_values += self.modes.event_values(t, y, mode, friction)
            if minor is not None:
                chosen_values.append(self.c.loop_minors(t, y, p)[minor[0]])
            return np.array(chosen_values)
        interior = 2 if mode.groups else 0
        watch = EventWatch(values, directions, zero_before, interior)
        locked = {k: mode.flags[self.switch_index.index(i)]
                  for k, i in enumerate(chosen) if i in self.switch_index}
        watch.start_sides = locked
        return watch

    # ---------------------------------------------------------------- events
    def _after_event(self, t, y, mode, fired, muted):
        """The stop, the new mode, the state and the muted switches after events."""
        t = float(t)
        kinds = [self._watch_map[i] for i in fired]
        if any(source == "minor" for source, _ in kinds):
            self.loops.check_singular(t, y, self.modes.p(mode))   # else a regular crossing
        stops = [i for source, i in kinds if source == "compiled" and i in self.stop_index]
        switches = {i for source, i in kinds if source == "compiled" and i in self.switch_index}
        muted = self._chattering(t, switches, muted)
        sticking, arrived = self._friction_events(kinds)
        y, touching, resting = jump(self.modes, t, y, mode, arrived, self.events)
        new_mode = self.modes.decide(t, y, self._flags(t, y, mode, muted),
                                     at_rest=sticking + sorted(resting), events=self.events,
                                     touching=touching)
        for k in sticking:
            if k in new_mode.stuck:
                self.events.append(Event(t, "stick", self.c.frictions[k],
                                         "sliding stopped, held by friction"))
        for k in sorted(mode.free - new_mode.free):
            self.events.append(Event(t, "engage", self.c.frictions[k], "magnitude positive"))
        for k in sorted(new_mode.free - mode.free):
            self.events.append(Event(t, "free", self.c.frictions[k], "magnitude zero"))
        y = self.modes.project(t, y, new_mode)
        if stops:
            label = self.c.stop_labels[self.stop_index.index(stops[0])]
            self.events.append(Event(t, "end", label, "stop condition met"))
            return label, new_mode, y, muted
        return None, new_mode, y, muted

    def _friction_events(self, kinds):
        """The frictions whose sliding speed reached zero and the stop limits reached
        (element indices of the friction modes) among the fired events."""
        fired = [self._friction_watched[j] for source, j in kinds if source == "friction"]
        sticking = [index for kind, index, _, _ in fired if kind == "stick"]
        arrived = [self.modes.k + index for kind, index, _, _ in fired if kind == "gap"]
        return sticking, arrived

    def _flags(self, t, y, mode, muted):
        """The side of each switching function at ``(t, y)``; one that is exactly zero
        takes the side it moves to (looked up a moment later along the motion); muted
        ones are unlocked (0)."""
        if not self.switch_index:
            return ()
        size = len(self.c.event_kinds)
        p = self.modes.p(mode)

        def sides(t_value, y_value):
            out = [0.0] * size
            self.c.raw["events"](t_value, _floats(y_value), p, out)
            return np.sign([out[i] for i in self.switch_index])
        flags = sides(t, y)
        if not np.all(flags):
            span = self.scene.time_limit - self.scene.t_start
            delta = 1e-9 * max(span, 1e-300)
            ahead = sides(t + delta, y + delta * np.asarray(self.c.rhs(t, y, p)))
            flags = np.where(flags == 0, ahead, flags)
        flags = np.where(flags == 0, 1.0, flags)
        for j, i in enumerate(self.switch_index):
            if i in muted:
                flags[j] = 0.0
        return tuple(float(f) for f in flags)

    def _chattering(self, t, switches, muted):
        """Switching functions that fire again at the same instant are left to the
        solver for the next segment (a ``sign`` of a speed that flips back and forth)."""
        last = getattr(self, "_last_switch", {})
        again = {i for i in switches
                 if i in last and t - last[i] <= _SAME_INSTANT * 1e3 * max(1.0, abs(t))}
        last.update({i: t for i in switches})
        self._last_switch = last
        return again

    # ---------------------------------------------------------------- methods
    def _choose(self, mode, t, y):
        if not self.auto:
            return self.method, "named in the scene"
        p = self.modes.p(mode)
        method, why = choose_method(self.c, p, y, t, self.scene.time_limit, self.scene.rtol)
        previous = next(reversed(self.stats["methods"]), None) if self.stats["methods"] else None
        if previous is not None and previous != method:
            self._record_switch(t, previous, method, why)
        return method, why

    def _switch(self, t, old, new, why):
        self._record_switch(t, old, new, why)
        return new, why

    def _record_switch(self, t, old, new, why):
        self.stats["switches"].append({"t": float(t), "from": old, "to": new, "why": why})

    def _after_failure(self, t, y, mode, method, message):
        """The next method to try after ``method`` failed at ``(t, y)``, or the error."""
        self._failed.append(method)
        tried = self._failed
        if self.auto:
            for candidate in fallbacks(method, self.scene.rtol):
                if candidate not in tried:
                    self._record_switch(t, method, candidate, f"retry after {method} failed: "
                                        f"{message}")
                    return candidate, "retry"
        raise SimulationError(
            f"integration failed at t = {t:.6g} s with {' then '.join(tried)}: {message}; "
            f"state {self._state_text(y)}" + self._diagnosis(t, y, mode))

    # ---------------------------------------------------------------- checks
    def _check_budget(self, t, h, method):
        steps, budget = self.stats["steps"], self.budget
        elapsed = time.perf_counter() - self.started
        over = None
        if budget.max_steps is not None and steps > budget.max_steps:
            over = f"{steps} steps exceed the step budget of {budget.max_steps}"
        elif budget.max_wall_time is not None and elapsed > budget.max_wall_time:
            over = f"{elapsed:.3g} s of wall time exceed the budget of {budget.max_wall_time} s"
        if over:
            raise SimulationError(
                f"integration stopped at t = {t:.6g} s of {self.scene.time_limit:.6g} s in "
                f"scene {self.scene.name!r}: {over} ({method}, last step {h:.3g} s). Try a "
                "looser rtol, a shorter t_end, method='auto' if another was named, or a "
                "larger budget (Scene(max_steps=..., max_wall_time=...))")

    def _report(self, t, t_end):
        if self.progress is None:
            return
        now = time.perf_counter()
        if now - self.last_report >= 0.25:
            self.last_report = now
            self.progress(t, t_end)

    def _check_mass(self, t, y):
        """Refuse a start where the mass matrix is not positive definite (on the motions
        closed loops allow)."""
        terms = self.c.terms(t, y, self.modes.p(Mode()))
        mass = terms["mass"]
        self.mass_scale = float(np.max(np.abs(mass), initial=0.0))
        if self.c.constraints:
            from .friction import _allowed_motions
            basis = _allowed_motions(terms["constraint_gradient"], self.n)
            mass = basis.T @ mass @ basis
            if np.all(np.linalg.eigvalsh(mass) > 0):
                return
            raise SingularMassError(", ".join(self.c.coordinates), t, y)
        try:
            np.linalg.cholesky(mass)
        except np.linalg.LinAlgError:
            worst = int(np.argmin(np.diag(mass))) if self.n else 0
            raise SingularMassError(self.c.coordinates[worst], t, y) from None

    def _check_finite(self, t, y):
        if not np.all(np.isfinite(y)):
            raise SimulationError(f"integration failed at t = {t:.6g} s: the state became "
                                  f"non-finite ({self._state_text(y)})")

    def _diagnosis(self, t, y, mode) -> str:
        """Why the equations fail at a state: an evaluation fault or a mass matrix that
        is (nearly) singular there (a dead centre of the chosen coordinate)."""
        p = self.modes.p(mode)
        self.loops.check_singular(t, y, p)
        try:
            values = np.asarray(self.c.rhs(t, y, p), dtype=float)
            mass = self.c.terms(t, y, p)["mass"]
            eigenvalues = np.linalg.eigvalsh(mass)
        except (ArithmeticError, ValueError, np.linalg.LinAlgError) as error:
            return (f". The equations cannot be evaluated there: {type(error).__name__}: "
                    f"{error}")
        scale = max(abs(eigenvalues[-1]), getattr(self, "mass_scale", 0.0), 1e-300)
        if eigenvalues[0] <= 1e-6 * scale:
            return (f". The mass matrix is nearly singular there (smallest eigenvalue "
                    f"{eigenvalues[0]:.3g} of {eigenvalues[-1]:.3g}): the reduced inertia of "
                    f"{', '.join(self.c.coordinates)} vanishes at this configuration, a "
                    "dead centre of the chosen coordinate")
        if not np.all(np.isfinite(values)):
            return ". The equations give non-finite values there (overflow or division by zero)"
        return ""

    def _state_text(self, y):
        return ", ".join(f"{name} = {value:.6g}" for name, value in zip(self.c.state_names, y))

    def _max_step(self, compiled):
        """The longest step of a segment with stuck elements, where the state barely
        moves and the solver's steps would grow past changes of the loads: 1/200 of the
        run, and 1/16 of the shortest period of a sine or cosine of t in the forcing."""
        span = self.scene.time_limit - self.scene.t_start
        out = [0.0] * compiled.meta["periods"]
        compiled.raw["periods"](self.scene.t_start, [0.0] * (2 * self.n),
                                self.modes.p(Mode()), out)
        return min([span / 200] + [period / 16 for period in out if period > 0])

    def _result(self, reason) -> Result:
        return Result(self.c, self.trajectory, self.events, reason, dict(self.stats),
                      self.base, self.scene, self.mechanism_name, self.units, self.modes)


def _floats(y):
    return y.tolist() if type(y) is np.ndarray else y


def _fast_rhs(raw, p, size):
    """solve_ivp's ``fun(t, y)`` over a generated ``rhs(t, y, p, out)``."""
    def fun(t, y):
        out = [0.0] * size
        raw(t, y.tolist(), p, out)
        return out
    return fun


_EVALUATION_ERRORS = (ArithmeticError, ValueError, SimulationError, np.linalg.LinAlgError)


def _tolerant(function, shape):
    """``function`` as the solver should see it: NaN where the equations cannot be
    evaluated (an overflowing trial stage, a singular mass matrix there), so the step is
    rejected and shrunk as for any NaN. Real failures surface as a collapsing step."""
    failed = np.full(shape, np.nan)

    def guarded(t, y):
        try:
            return function(t, y)
        except _EVALUATION_ERRORS:
            return failed
    return guarded
