"""The simulation driver: a run as a sequence of segments.

A segment is integrated with one friction mode, one set of locked branches, one method
and one backend; it ends at an event (a stop condition, a friction element sticking,
releasing or engaging, a stop's limit reached: an impact, :mod:`mechdyn.simulate.contacts`; a
switch of a ``Piecewise``), when its method no longer fits the problem (stiffness
measured both ways), or when its method fails. A segment's backend follows from the
scene, the installation and the segment's kind only
(:class:`~mechdyn.simulate.methods.BackendPlan`), never from elapsed time or from what
ran before. The driver then decides what comes next: the new friction mode
(:mod:`mechdyn.simulate.friction`), the method (:mod:`mechdyn.simulate.methods`: the
stiffness is measured again at every segment start), or another method from the last
accepted state after a failure. ``stats["switches"]`` records every change of method
(time, from, to, why).

Budgets bound the work: a run that exceeds its steps or its wall time stops with a
:class:`~mechdyn.errors.SimulationError` naming the scene, the time reached, the step size
and the method, and what to try; like every failure it carries the result computed so far
(``error.partial``). ``progress(t, t_end)`` is called about every quarter second.
"""
from __future__ import annotations

import time

import numpy as np

from mechdyn.simulate.contacts import jump
from mechdyn.errors import SimulationError
from mechdyn.simulate.events import Event
from mechdyn.simulate.friction import FrictionModes, Mode
from mechdyn.simulate.loop_watch import LoopSingularError, LoopWatch
from mechdyn.simulate.methods import (StiffnessMonitor, backend_plan, explicit_for, fallbacks,
                      motion_jacobian, segment_tolerances, stiff_for)
from mechdyn.simulate.result import Result
from mechdyn.simulate.run_checks import (Budget, check_finite, check_mass, check_scales,
                                         check_singular_mass, diagnosis, state_text)
from mechdyn.simulate.segments import compiled_runner, scipy_runner, watched_events
from mechdyn.simulate.threads import single_threaded_blas
from mechdyn.simulate.time_events import time_events
from mechdyn.simulate.trajectory import Segment, Trajectory

__all__ = ["Budget", "Driver"]

_CHUNK = {"scipy": 200, "compiled": 20_000}   # steps between progress/budget checks
_SAME_INSTANT = 1e-12        # relative time under which events count as simultaneous
_EVENT_LOOP_LIMIT = 200      # events at one instant before the run is called stuck
_COLLAPSE = 1e-12            # a step shorter than this fraction of the run has collapsed
_PROGRESS = 1e-6             # a segment this much of the rest long clears past failures
_EDGE = 1e-9                 # a domain argument this far down from its start: the edge
_NEAR_EDGE = 1e-6            # ... and where a failing method stopped: the cause
_SETTLE_STEPS = 200          # a method switch after fewer steps ...
_HOLD_STEPS = 1000           # ... holds the next segment's method for this many steps
_EPS = float(np.finfo(float).eps)


class Driver:
    """Runs one scene: ``Driver(compiled, base, scene, atol, mechanism, ...).run(y0)``.

    ``base`` the parameter values; the method (``"auto"`` or a name) and backend
    (``"auto"``, ``"scipy"``, ``"compiled"``) come from the scene unless given."""

    def __init__(self, compiled, base, scene, atol, mechanism, budget=None, progress=None,
                 backend=None):
        self.c, self.base, self.scene, self.atol = compiled, list(base), scene, atol
        self.auto = scene.method == "auto"
        self.plan = backend_plan(compiled, scene.method, backend or scene.backend)
        self.modes = FrictionModes(compiled, base, scene.time_limit - scene.t_start)
        self.mechanism_name, self.units = mechanism.name, mechanism.units
        self.budget = budget or Budget()
        self.progress = progress
        self.n = compiled.dof
        self.trajectory = Trajectory()
        self.events: list[Event] = []
        self.stats = {"method": "", "methods": {}, "backends": {}, "steps": 0, "nfev": 0,
                      "njev": 0, "nlu": 0, "segments": 0, "switches": [], "wall_time": 0.0}
        self.max_step = self._max_step()
        self.loops = LoopWatch(compiled, scene.rtol)
        self.mass_scale = 0.0         # M's largest entry at the start (check_mass)
        self.span = scene.time_limit - scene.t_start
        self.scratch = {}             # the compiled chunks' work arrays, for every segment
        if self.plan.active and compiled.constraints:
            from mechdyn.compile.numba_model import loop_projection
            self.modes.loop_projection = loop_projection(compiled)
        self._switches = [i for i, (kind, _) in enumerate(compiled.event_kinds)
                          if kind == "switch"]

    # ------------------------------------------------------------------ the run
    def run(self, y0) -> Result:
        """Integrate from ``y0`` to the scene's end (BLAS single-threaded meanwhile:
        :mod:`mechdyn.simulate.threads`)."""
        with single_threaded_blas():
            return self._run(y0)

    def _run(self, y0) -> Result:
        t, t_end = self.scene.t_start, self.scene.time_limit
        y = np.array(y0, dtype=float)
        self.started = self.last_report = time.perf_counter()
        reason = "t_end"
        try:
            domains = self._domains = self._check_domains(t, y, self.modes.p(Mode()))
            self.times = time_events(self.c, self.modes.p(Mode()), y, t, t_end,
                                     self.periods)
            terms = self._start_terms(t, y)
            self.mass_scale = check_mass(self.c, terms, t, y)
            check_scales(self.c, terms, t, y, self.scene.name)
            muted, instant, count, h = set(), None, 0, None
            y, touching, resting = jump(self.modes, t, y, None, (), self.events)
            mode = self.modes.decide(t, y, self._flags(t, y, Mode(), muted),
                                     at_rest=resting, events=self.events, touching=touching)
            y = self.modes.project(t, y, mode)
            method = self._choose(mode, t, y)
            self._failed = []
            while t < t_end:
                t_before = t
                outcome, h = self._segment(mode, method, t, y, t_end, h, muted)
                t, y = outcome.t, outcome.y
                if outcome.status != "failed" and t - t_before > _PROGRESS * (t_end - t_before):
                    self._failed = []
                if outcome.status == "finished":
                    break
                if outcome.status == "drift":          # closed loops: back onto them
                    self.loops.check_margin(t, y, self.modes.p(mode))
                    y = self.modes.project(t, y, mode)
                    self.stats["projections"] = self.stats.get("projections", 0) + 1
                elif outcome.status == "stiff":
                    before = method
                    method = self._after_stiffness(t, y, method, mode)
                    # after a short segment, or no switch: the next keeps its method
                    self._settle = method == before or self._segment_steps < _SETTLE_STEPS
                elif outcome.status == "failed":
                    method, h = self._after_failure(t, y, mode, method, outcome.message), None
                else:
                    count = count + 1 if instant is not None and \
                        t - instant <= _SAME_INSTANT * max(1.0, abs(t)) else 1
                    instant = t
                    if count > _EVENT_LOOP_LIMIT:
                        raise SimulationError(f"integration failed at t = {t:.6g} s: "
                                              f"{count} events at the same instant (the "
                                              "modes cannot settle)")
                    stop, mode, y, muted = self._after_event(t, y, mode, outcome.fired,
                                                             muted)
                    if stop is not None:
                        reason = stop
                        self.trajectory.segments[-1].settle(y)
                        self.trajectory.changed()
                        break
                    method, h = self._choose(mode, t, y, method), None
        except SimulationError as error:
            self._finish()
            if isinstance(error, LoopSingularError):
                self.loops.trim(self.trajectory, self.events, error, self.modes.p(Mode()))
            error.partial = self._result("failed: " + str(error))
            if not str(error).startswith("integration"):
                error.args = (f"integration failed: {error}",)
            raise
        if reason == "t_end" and self.c.stop_labels:
            reason = "t_end (stop condition not reached)"
        try:
            self._check_domains(t, y, self.modes.p(mode), start=domains)
        except SimulationError as error:
            self._finish()
            error.partial = self._result("failed: " + str(error))
            raise
        self._finish()
        return self._result(reason)

    def _finish(self):
        self.stats["wall_time"] = time.perf_counter() - self.started
        used = self.stats["methods"]
        self.stats["method"] = "+".join(used) if used else self.scene.method

    # ------------------------------------------------------------- a segment
    def _segment(self, mode, method, t0, y0, t_end, h, muted):
        """Integrate from ``(t0, y0)`` until something happens; returns the outcome and
        the last step size."""
        p = self.modes.p(mode)
        method = self.plan.method(method, mode)
        backend = self.plan.backend(method, mode)
        watched = watched_events(self.modes, self.scene, mode, muted, t0, y0,
                                 self.loops.watched_minor(t0, y0, p))
        self._watched = watched
        t_stop, timed = self.times.segment_end(t0, t_end, watched) if self.times \
            else (t_end, [])
        rtol, atol = self.scene.rtol, self.atol
        if self.auto and backend == "scipy":
            rtol, atol = segment_tolerances(method, rtol, atol)
        segment = self.trajectory.add(Segment(t0, y0, mode, method))
        self.stats["segments"] += 1
        hold = _HOLD_STEPS if getattr(self, "_settle", False) else 0
        self._settle = False
        if backend == "compiled":
            run = compiled_runner(self, self.plan.functions_for(mode, method), mode, method,
                                  t0, y0, t_stop, h, watched, rtol, atol, segment,
                                  switch=self.auto)
        else:
            monitor = None
            if self.auto and not mode.groups:
                monitor = StiffnessMonitor(method, lambda t, y: motion_jacobian(self.c, t, y,
                                                                                p), rtol)
            run = scipy_runner(self, mode, method, t0, y0, t_stop, h, watched, rtol, atol,
                               monitor, segment, _COLLAPSE * self.span,
                               self.loops.drifted(y0, p))
        counted = dict.fromkeys(("steps", "nfev", "njev", "nlu"), 0)
        held = run.hold_switching() if hold and self.auto else None
        while True:
            outcome = run.advance(min(_CHUNK[backend], hold) if held else _CHUNK[backend])
            counts = run.counts
            if held and counts["steps"] >= hold:
                held = held()                  # the method may change again from here
            self.trajectory.changed()
            counted = self._count(counts, counted, method, backend)
            self._check_budget(outcome.t, run.h, method)
            self._report(outcome.t, t_end)
            self._segment_steps = counts["steps"]
            if outcome.status == "chunk":
                continue
            if outcome.status != "failed":
                check_finite(self.c, outcome.t, outcome.y)
            if timed and outcome.status in ("finished", "event") and outcome.t >= t_stop:
                outcome.status = "event"                    # a crossing of t alone
                outcome.fired = sorted(set(outcome.fired) | set(timed))
            return outcome, run.h

    def _count(self, counts, counted, method, backend):
        for key in counted:
            self.stats[key] += counts[key] - counted[key]
        steps = counts["steps"] - counted["steps"]
        for table, name in ((self.stats["methods"], method), (self.stats["backends"], backend)):
            table[name] = table.get(name, 0) + steps
        return dict(counts)

    # ---------------------------------------------------------------- events
    def _after_event(self, t, y, mode, fired, muted):
        """The stop, the new mode, the state and the muted switches after events."""
        t = float(t)
        kinds = [self._watched[i] for i in fired]
        for w in kinds:
            if w.kind in ("domain", "mass"):
                self._no_real_value(t, y, w.index)
        if any(w.kind == "minor" for w in kinds):
            self.loops.check_singular(t, y, self.modes.p(mode))   # else a regular crossing
        muted = self._chattering(t, {w.index for w in kinds if w.kind == "switch"})
        sticking = [w.element for w in kinds if w.kind == "stick"]
        arrived = [self.modes.k + w.element for w in kinds if w.kind == "gap"]
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
        stops = [w.element for w in kinds if w.kind == "stop"]
        if stops:
            label = self.c.stop_labels[stops[0]]
            self.events.append(Event(t, "end", label, "stop condition met"))
            return label, new_mode, y, muted
        return None, new_mode, y, muted

    def _no_real_value(self, t, y, index):
        """Raise: an element's expression has no real value beyond ``(t, y)``."""
        kind, label = self.c.event_kinds[index]
        if kind == "mass":              # det M / prod M_ii fell below its floor
            check_singular_mass(self.c, self.modes.p(Mode()), t, y, self.mass_scale, None)
        raise SimulationError(f"integration stopped at t = {t:.6g} s: {label} has no real "
                              f"value beyond {state_text(self.c, y)} (the argument of a "
                              "root, power, logarithm or arcsine there turns negative)")

    def _check_domains(self, t, y, p, start=None, edge=None):
        """Refuse a state where an element's expression has no real value; at the end
        of a run (``start``: the values at the start), one that has crept up to the edge
        of its domain, where the equations become singular (a stall, not a result)."""
        values = self.c.events(t, y, p)
        for i, (kind, label) in enumerate(self.c.event_kinds):
            if kind not in ("domain", "mass"):
                continue
            if values[i] < 0:
                self._no_real_value(t, y, i)
            if start is not None and start[i] > 0 and values[i] <= (edge or _EDGE) * start[i] \
                    and kind == "domain" and not label.startswith("output "):
                raise SimulationError(
                    f"integration stopped at t = {t:.6g} s: the motion reaches the edge of "
                    f"{label} at {state_text(self.c, y)}: the argument of its root, power, "
                    "logarithm or arcsine is zero there and the expression has no real "
                    "value beyond (the equations are singular at the edge); the "
                    "declaration does not describe this motion")
        return values

    def _flags(self, t, y, mode, muted):
        """The side of each switching function at ``(t, y)``; one that is exactly zero
        takes the side it moves to (looked up a moment later along the motion); muted
        ones are unlocked (0)."""
        switches = self._switches
        if not switches:
            return ()
        p = self.modes.p(mode)

        def sides(t_value, y_value):                # short lists: plain Python
            values = self.c.events(t_value, y_value, p)
            return [_sign(values[i]) for i in switches]
        flags = sides(t, y)
        if not all(flags):
            delta = 1e-9 * max(self.span, 1e-300)
            ahead = sides(t + delta, y + delta * np.asarray(self.c.rhs(t, y, p)))
            flags = [a if f == 0 else f for f, a in zip(flags, ahead)]
        return tuple(0.0 if i in muted else (f or 1.0) for i, f in zip(switches, flags))

    def _chattering(self, t, switches):
        """Switching functions that fire again at the same instant are left to the
        solver for the next segment (a ``sign`` of a speed that flips back and forth)."""
        last = getattr(self, "_last_switch", {})
        again = {i for i in switches
                 if i in last and t - last[i] <= _SAME_INSTANT * 1e3 * max(1.0, abs(t))}
        last.update({i: t for i in switches})
        self._last_switch = last
        return again

    # ---------------------------------------------------------------- methods
    def _choose(self, mode, t, y, previous=None):
        method = self.plan.choose(self.modes.p(mode), mode, t, y, self.scene)
        if previous is not None and previous != method:
            self._record_switch(t, previous, method, self.plan.why)
        return method

    def _after_stiffness(self, t, y, method, mode):
        """The method after a stiffness test fired; an explicit method is kept where the
        eigenvalues show only oscillations the tolerance asks to resolve (user guide)."""
        self.plan.forget()
        if self.plan.stiff(method):
            return self._switch(t, method, self.plan.method(explicit_for(self.scene.rtol),
                                                              mode),
                                "the stiff method's steps stay within the explicit "
                                "method's stability (not stiff)")
        measured = self.plan.choose(self.modes.p(mode), mode, t, y, self.scene)
        if not self.plan.stiff(measured) and self.plan.why == "no stiff modes":
            return method
        return self._switch(t, method, self.plan.method(stiff_for("scipy"), mode),
                            "the explicit method is held at its stability limit (stiff)")

    def _switch(self, t, old, new, why):
        self._record_switch(t, old, new, why)
        return new

    def _record_switch(self, t, old, new, why):
        self.stats["switches"].append({"t": float(t), "from": old, "to": new, "why": why})

    def _after_failure(self, t, y, mode, method, message):
        """The next method to try after ``method`` failed at ``(t, y)``, or the error."""
        self._failed.append(method)
        self.plan.forget()
        p = self.modes.p(mode)        # a failure at the edge of an expression's domain
        self._check_domains(t, y, p, start=self._domains, edge=_NEAR_EDGE)
        check_singular_mass(self.c, p, t, y, self.mass_scale, _EPS / self.scene.rtol)
        if self.auto:
            for candidate in fallbacks(method, self.scene.rtol, self.plan.active):
                if candidate not in self._failed:
                    self._record_switch(t, method, candidate,
                                        f"retry after {method} failed: {message}")
                    return candidate
        self.loops.check_singular(t, y, p)
        raise SimulationError(
            f"integration failed at t = {t:.6g} s with {' then '.join(self._failed)}: "
            f"{message}; state {state_text(self.c, y)}"
            + diagnosis(self.c, p, t, y, self.mass_scale))

    # ---------------------------------------------------------------- checks
    def _check_budget(self, t, h, method):
        over = self.budget.exceeded(self.stats["steps"], time.perf_counter() - self.started)
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

    def _start_terms(self, t, y):
        """The equations' terms at the start; a start where they cannot be evaluated
        (a division by zero, a logarithm of zero) is a named error, not a traceback."""
        try:
            return self.c.terms(t, y, self.modes.p(Mode()))
        except (ArithmeticError, ValueError) as error:
            raise SimulationError(
                f"scene {self.scene.name!r}: the equations cannot be evaluated at the start "
                f"(t = {t:.6g} s, {state_text(self.c, y)}): {type(error).__name__}: "
                f"{error}") from None

    def _max_step(self):
        """The longest step of a segment with stuck elements, where the state barely
        moves and the solver's steps would grow past changes of the loads: 1/200 of the
        run, and 1/16 of the shortest period of a sine or cosine of t in the forcing or
        the events (which bounds every segment's step: ``period_step``)."""
        span = self.scene.time_limit - self.scene.t_start
        out = [0.0] * self.c.meta["periods"]
        self.c.raw["periods"](self.scene.t_start, [0.0] * (2 * self.n),
                              self.modes.p(Mode()), out)
        self.periods = [period for period in out if period > 0]
        self.period_step = min([np.inf] + [period / 16 for period in self.periods])
        return min(span / 200, self.period_step)

    def _result(self, reason) -> Result:
        return Result(self.c, self.trajectory, self.events, reason, dict(self.stats),
                      self.base, self.scene, self.mechanism_name, self.units, self.modes)


def _sign(value):
    """-1.0, 0.0 or 1.0 as ``numpy.sign``; NaN stays NaN."""
    return 1.0 if value > 0 else -1.0 if value < 0 else 0.0 if value == 0 else value
