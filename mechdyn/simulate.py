"""Simulation: integrate a compiled scene with scipy's solvers, stop conditions and
Coulomb friction with true stick and slip.

Friction follows the state machine of Modelica's friction elements. A sliding element
pushes with ``-sign * magnitude`` (its sign held fixed for the segment) until its sliding
rate reaches zero (an event located on the solver's dense output). There the speeds are
projected so the rate is exactly zero, and the element sticks if the constraint force
needed to hold it, ``lambda`` from ``[M -G'; G 0] [a; lambda] = [f; -bias]``, stays within
its magnitude; a stuck element releases (an event on ``magnitude - |lambda|``) and slides
the way the net force pushes. A coordinate held by a stuck friction keeps exactly zero
speed. No ``sign()`` chattering, no smoothing creep.

Closed loops (``Equations.constraints``, see :mod:`mechdyn.loop_code`): the initial
state is assembled (:func:`mechdyn.assembly.assemble`: Newton on the dependent positions
from the scene's guesses, ``G u = -dg/dt`` for the dependent speeds); the generated
``rhs`` solves ``M a = f + G' lambda``, ``G a = -bias`` with the loops always active (and
``_kkt`` stacks them with stuck frictions); after a step where the drift ``|g|`` or
``|G u + dg/dt|`` exceeds rtol times the loop's size the segment ends there and the state
is projected back (:func:`mechdyn.assembly.project`); the largest minor of ``G`` is
watched as an event, and where it changes sign with every minor small the run stops
with :class:`~mechdyn.loop_code.LoopSingularError`; a loop's name as an output records
its multipliers (:meth:`_Run.loop_multipliers`).

>>> import mechdyn as md
>>> model = md.load_model("models/shoe_brake.py")
>>> res = model.mechanism.simulate(model.scenes["braking"], model.params)
>>> round(res.t_end, 9), round(res.final(model.mechanism.coordinates[0]), 6)
(50.0, 2500.0)
"""
from __future__ import annotations

import math
import time

import numpy as np
import sympy as sp
from scipy.optimize import brentq

from .assembly import closure_parts, project
from .compile import SingularMassError, compile_scene
from .elements import Link
from .errors import ParameterError, SceneError, SimulationError
from .loop_code import LOOP_MARGIN, LoopSingularError
from .result import Event, Result, Trajectory
from .scene import DEFAULT_ATOL, Scene
from .stepping import METHODS, WITH_JACOBIAN, run_steps

__all__ = ["simulate", "initial_state", "choose_method", "METHODS"]

_STIFFNESS_LIMIT = 2000.0   # explicit steps forced by stability alone; see choose_method
_EPS = np.finfo(float).eps


def simulate(mechanism, scene: Scene, params: dict) -> Result:
    """Integrate ``scene`` on ``mechanism`` with parameter values ``params``.

    Raises :class:`SimulationError` (with ``.partial``, the result up to the failure)
    when the integration fails: NaN or overflow, a singular mass matrix, step size
    collapse.
    """
    if not isinstance(scene, Scene):
        raise SceneError(f"simulate() needs a md.Scene, got {scene!r}")
    compiled = compile_scene(mechanism, scene)
    p = compiled.parameter_vector(params)
    _check_links(mechanism, params)
    y0 = initial_state(compiled, mechanism, scene, params)
    atol = _atol_vector(compiled, mechanism, scene)
    method = scene.method
    if method == "auto":
        method = choose_method(compiled, p, y0, scene.t_start, scene.time_limit, scene.rtol)
    elif method not in METHODS:
        raise SceneError(f"scene {scene.name!r}: unknown method {method!r}; "
                         f"use 'auto' or one of {', '.join(METHODS)}")
    return _Run(compiled, p, scene, method, atol, mechanism).execute(y0)


# --------------------------------------------------------------------- inputs
def _by_name(params):
    return {str(k): v for k, v in params.items()}


def _check_links(mechanism, params):
    """Refuse parameter values that make a link's mass or inertia negative."""
    values = {name: sp.Float(value) for name, value in _by_name(params).items()
              if isinstance(value, (int, float))}
    for link in mechanism.elements.values():
        if not isinstance(link, Link):
            continue
        for attribute in ("m", "J"):
            expr = getattr(link, attribute)
            if expr.is_number:
                continue                     # numbers were checked when declared
            value = expr.xreplace({s: values[s.name] for s in expr.free_symbols
                                   if s.name in values})
            if value.is_number and value < 0:
                raise ParameterError(f"link {link.name!r}: {attribute} = {expr} = {value} is "
                                     "negative; masses and inertias must not be negative")


def initial_state(compiled, mechanism, scene, params) -> np.ndarray:
    """The scene's initial state vector ``[q..., u...]``, checked and evaluated."""
    n = compiled.dof
    declared = {q.func.__name__ for q in mechanism.coordinates}
    slots = {}
    for i, name in enumerate(compiled.coordinates):
        slots[("q", name)] = i
        slots[("u", name)] = n + i
    values = {str(k): v for k, v in params.items()}
    y0 = np.full(2 * n, np.nan)
    for key, value in scene.initial.items():
        slot = _initial_slot(key, declared, scene)
        if slot[1] not in compiled.coordinates:
            continue                                  # a coordinate made rigid
        expr = value if isinstance(value, sp.Basic) else None
        if expr is not None:
            expr = expr.subs({s: values[s.name] for s in expr.free_symbols if s.name in values})
            if not expr.is_number:
                raise SceneError(f"scene {scene.name!r}: initial value of {key} = {value} has "
                                 f"no number (unknown: {sorted(map(str, expr.free_symbols))})")
            value = expr
        try:
            y0[slots[slot]] = float(value)
        except (TypeError, ValueError):
            raise SceneError(f"scene {scene.name!r}: initial value of {key} = {value!r} is "
                             "not a number") from None
        if not math.isfinite(y0[slots[slot]]):
            raise SceneError(f"scene {scene.name!r}: initial value of {key} is not finite")
    # Closed loops: dependent speeds are solved, dependent positions are guesses.
    solved = [n + i for i in range(n) if compiled.constraints and i not in compiled.independent]
    missing = [compiled.state_names[i] for i in range(2 * n)
               if np.isnan(y0[i]) and i not in solved]
    if missing:
        guesses = (" and a guess for each dependent coordinate, which picks the assembly "
                   "branch" if solved else "")
        raise SceneError(f"scene {scene.name!r}: missing initial values for "
                         f"{', '.join(missing)} (give them in initial={{q: ..., "
                         f"md.speed(q): ...}}{guesses})")
    if compiled.constraints:
        from .assembly import assemble
        return assemble(compiled, y0, compiled.parameter_vector(params), scene.t_start,
                        scene.name, [i for i in solved if not np.isnan(y0[i])])
    return y0


def _initial_slot(key, declared, scene, what="initial value"):
    from .symbols import is_coordinate, t
    if is_coordinate(key) and key.func.__name__ in declared:
        return ("q", key.func.__name__)
    if isinstance(key, sp.Derivative) and is_coordinate(key.expr) and \
            key.variable_count == ((t, 1),) and key.expr.func.__name__ in declared:
        return ("u", key.expr.func.__name__)
    raise SceneError(f"scene {scene.name!r}: {what} given for {key}, which is not a "
                     f"declared coordinate or its speed (coordinates: {sorted(declared)})")


def _atol_vector(compiled, mechanism, scene):
    """A scalar atol, or the vector of a per-state dict (``"default"`` for the rest)."""
    if not isinstance(scene.atol, dict):
        return float(scene.atol)
    declared = {q.func.__name__ for q in mechanism.coordinates}
    vector = np.full(2 * compiled.dof, float(scene.atol.get("default", DEFAULT_ATOL)))
    for key, value in scene.atol.items():
        if key == "default":
            continue
        kind, name = _initial_slot(key, declared, scene, "atol")
        if name in compiled.coordinates:
            offset = compiled.dof if kind == "u" else 0
            vector[offset + compiled.coordinates.index(name)] = float(value)
    return vector


def choose_method(compiled, p, y0, t0, t_limit, rtol) -> str:
    """Pick an integrator by measuring the problem: the eigenvalues of the analytic
    Jacobian at the start against the slowest time scale of the run.

    - Damped fast modes (large negative real parts): stiff, Radau with the analytic
      Jacobian, once stability alone would cost an explicit method more than
      ``_STIFFNESS_LIMIT`` steps.
    - Undamped fast modes (large imaginary parts only) are real oscillations. At tight
      tolerances they must be resolved, which an explicit method does ~10x faster
      (measured: 1e5 rad/s coupling over 1 s, DOP853 39 s, Radau 385 s); at rtol >= 1e-6
      Radau steps over them (34 steps) and gives the rigid limit.
    - Otherwise DOP853 (rtol < 1e-6) or RK45.

    The slow scale is the smallest non-zero eigenvalue magnitude, or the run length when
    the motion has a rigid-body (zero) mode.
    """
    explicit = "DOP853" if rtol < 1e-6 else "RK45"
    try:
        if getattr(compiled, "constraints", None):   # closed loops: the allowed motion only
            from .assembly import manifold_jacobian
            jacobian = manifold_jacobian(compiled, t0, y0, p)
        else:
            jacobian = compiled.jac(t0, y0, p)
    except (ArithmeticError, ValueError, SimulationError):
        return explicit                           # the integration will name the fault
    if not np.all(np.isfinite(jacobian)):
        return explicit
    eigenvalues = np.linalg.eigvals(jacobian)
    magnitude = np.abs(eigenvalues)
    fastest = magnitude.max(initial=0.0)
    # A rigid-body mode is a double zero eigenvalue (a Jordan block): eig perturbs it by
    # about sqrt(eps) * |J|, far above eps, so "zero" is judged near sqrt(eps).
    nonzero = magnitude[magnitude > max(fastest, 1.0) * 1e-7]
    slowest = 1.0 / (t_limit - t0)
    if len(nonzero) == len(magnitude) and len(nonzero):
        slowest = nonzero.min()
    elif len(nonzero):
        slowest = max(slowest, min(nonzero.min(), 1.0))
    damped = np.max(-eigenvalues.real, initial=0.0)
    if damped / slowest > _STIFFNESS_LIMIT:
        return "Radau"
    if fastest / slowest > _STIFFNESS_LIMIT and rtol >= 1e-6:
        return "Radau"
    return explicit


# ------------------------------------------------------------------- the run
class _Mode:
    """Friction signs of one segment: +1/-1 sliding that way, 0 stuck."""

    def __init__(self, signs):
        self.signs = list(signs)
        self.stuck = [k for k, s in enumerate(signs) if s == 0]


class _Run:
    def __init__(self, compiled, p, scene, method, atol, mechanism):
        self.c, self.scene, self.method, self.atol = compiled, scene, method, atol
        self.n = compiled.dof
        self.k = len(compiled.frictions)
        self.base = p[:len(p) - self.k]
        self.trajectory = Trajectory(compiled)
        self.events: list[Event] = []
        self.stats = {"method": method, "steps": 0, "nfev": 0, "njev": 0, "nlu": 0,
                      "segments": 0, "failed_steps": 0}
        self.mechanism_name = mechanism.name
        self.units = getattr(mechanism, "units", {})
        self._minor_scale = None     # closed loops: size of G's largest minor at the start

    # ------------------------------------------------------------- friction
    def _terms(self, t, y, p):
        n, k = self.n, self.k
        v = self.c.terms(t, y, p)
        mass = np.array(v[:n * n]).reshape(n, n)
        forcing = np.array(v[n * n:n * n + n])
        o = n * n + n
        grads = np.array(v[o:o + k * n]).reshape(k, n)
        o += k * n
        bias, magnitude, rate = (np.array(v[o:o + k]), np.array(v[o + k:o + 2 * k]),
                                 np.array(v[o + 2 * k:o + 3 * k]))
        return mass, forcing, grads, bias, magnitude, rate

    def _constrained(self, t, y, p, stuck):
        """Accelerations and holding forces with the ``stuck`` frictions as constraints.

        Frictions along parallel directions (two brakes on one shaft) form one
        constraint; its holding force is shared in proportion to their magnitudes."""
        a, _, holding, magnitude = self._kkt(t, y, p, stuck)
        return a, holding, magnitude

    def _kkt(self, t, y, p, stuck):
        """``(a, loop multipliers, holding forces, magnitudes)`` with the closed loops'
        constraints (always active) and the ``stuck`` frictions'."""
        mass, forcing, grads, bias, magnitude, rate = self._terms(t, y, p)
        n = self.n
        groups = _parallel_groups(grads, stuck)
        g = np.array([grads[members[0][0]] for members in groups]).reshape(len(groups), n)
        b = np.array([bias[members[0][0]] for members in groups])
        loops = 0
        if self.c.constraints:
            _, loop_grads, _, loop_bias = closure_parts(self.c, t, y, p)
            loops = len(loop_grads)
            g, b = np.vstack([loop_grads, g]), np.concatenate([loop_bias, b])
        m = len(g)
        system = np.zeros((n + m, n + m))
        system[:n, :n] = mass
        system[:n, n:] = -g.T
        system[n:, :n] = g
        rhs = np.concatenate([forcing, -b])
        try:
            solution = np.linalg.solve(system, rhs)
        except np.linalg.LinAlgError:
            raise SingularMassError(", ".join(self.c.coordinates), t, y) from None
        holding = np.zeros(len(stuck))
        for lam, members in zip(solution[n + loops:], groups):
            capacity = sum(abs(alpha) * magnitude[k] for k, alpha in members)
            for k, alpha in members:
                share = magnitude[k] / capacity if capacity > 0 else 1.0 / len(members)
                holding[stuck.index(k)] = lam * share * math.copysign(1.0, alpha)
        return solution[:n], solution[n:n + loops], holding, magnitude

    def loop_multipliers(self, t, y, p, stuck):
        """The closed loops' multipliers lambda at a state (``M a = f + G' lambda``)."""
        if stuck:
            return self._kkt(t, y, p, stuck)[1]
        return np.array(self.c.multipliers(t, y, p))

    def _decide(self, t, y, forced=None):
        """Friction modes at a state: slide the way they move, else stick if they can.

        ``forced`` maps frictions whose release event fired to their sliding sign."""
        if not self.k:
            return _Mode([])
        forced = forced or {}
        _, _, _, _, _, rate = self._terms(t, y, self.base + [0.0] * self.k)
        speed_scale = 1.0 + float(np.max(np.abs(y[self.n:]), initial=0.0))
        signs = [math.copysign(1.0, r) if abs(r) > 1e-12 * speed_scale else 0.0 for r in rate]
        for k, sign in forced.items():
            signs[k] = sign
            self.events.append(Event(t, "slip", self.c.frictions[k],
                                     f"released, slides {'forward' if sign > 0 else 'backward'}"))
        while 0.0 in signs:
            stuck = [k for k, s in enumerate(signs) if s == 0]
            _, holding, magnitude = self._constrained(t, y, self.base + signs, stuck)
            excess = [abs(h) - magnitude[k] for h, k in zip(holding, stuck)]
            worst = int(np.argmax(excess))
            if excess[worst] <= 0:
                break
            kk = stuck[worst]
            signs[kk] = -math.copysign(1.0, holding[worst])
            self.events.append(Event(t, "slip", self.c.frictions[kk],
                                     f"slides {'forward' if signs[kk] > 0 else 'backward'}"))
        return _Mode(signs)

    def _project(self, t, y, mode):
        """Make the sliding rates of stuck frictions exactly zero (speeds projected with
        the mass matrix as metric, i.e. by an impulse)."""
        y = np.array(y, dtype=float)
        if self.c.constraints:
            y = project(self.c, t, y, self.base + mode.signs)
        if not mode.stuck:
            return y
        mass, _, grads, _, _, rate = self._terms(t, y, self.base + mode.signs)
        first = [members[0][0] for members in _parallel_groups(grads, mode.stuck)]
        g = grads[first]
        if self.c.constraints:      # least change keeping the loops' speeds closed
            _, loop_grads, rate_t, _ = closure_parts(self.c, t, y, self.base + mode.signs)
            rows = np.vstack([loop_grads, g])
            residual = np.concatenate([loop_grads @ y[self.n:] + rate_t, rate[first]])
            y[self.n:] -= np.linalg.lstsq(rows, residual, rcond=None)[0]
        else:
            w = np.linalg.solve(mass, g.T)
            y[self.n:] -= w @ np.linalg.solve(g @ w, rate[first])
        for k in mode.stuck:
            if self.c.frozen[k] >= 0:
                y[self.n + self.c.frozen[k]] = 0.0
        return y

    # -------------------------------------------------------- right-hand sides
    def _functions(self, mode):
        p = self.base + mode.signs
        rhs = self.c.rhs
        if not mode.stuck:
            jac = (lambda t, y: self.c.jac(t, y, p)) if self.method in WITH_JACOBIAN else None
            return (lambda t, y: rhs(t, y, p)), jac, p
        frozen = [self.c.frozen[k] for k in mode.stuck if self.c.frozen[k] >= 0]
        n = self.n

        def stuck_rhs(t, y):
            a, _, _ = self._constrained(t, y, p, mode.stuck)
            dy = np.concatenate([y[n:], a])
            for i in frozen:
                dy[i] = 0.0
                dy[n + i] = 0.0
            return dy
        return stuck_rhs, None, p

    def _event_functions(self, mode, p, t0, y0):
        """(function, direction, kind, index) of the events watched in a segment."""
        watched = []
        for i, stop in enumerate(self.c.stops):
            g0 = stop(t0, y0, p)
            if g0 != 0:
                watched.append(((lambda t, y, f=stop: f(t, y, p)), -math.copysign(1, g0),
                                "stop", i))
        for k, sign in enumerate(mode.signs):
            if sign != 0:
                watched.append(((lambda t, y, k=k: self._terms(t, y, p)[5][k]), -sign,
                                "stick", k))
            else:
                position = mode.stuck.index(k)
                _, lam, magnitude = self._constrained(t0, y0, p, mode.stuck)
                # Held exactly at the limit: start the margin just above zero so the
                # next increase of the load releases it.
                offset = max(0.0, abs(lam[position]) - magnitude[k]) \
                    + 1e-12 * (magnitude[k] + abs(lam[position]))

                def holding(t, y, k=k, position=position, offset=offset):
                    _, lam, magnitude = self._constrained(t, y, p, mode.stuck)
                    return magnitude[k] - abs(lam[position]) + offset
                watched.append((holding, -1, "release", k))
        if self.c.constraints:   # closed loops: the largest minor of G changes sign ...
            minors = np.abs(self.c.loop_minors(t0, y0, p))
            k = int(np.argmax(minors))
            if self._minor_scale is None:
                self._minor_scale = minors[k]          # at the assembled start
            if minors[k] < LOOP_MARGIN * self._minor_scale:
                self._loop_singular(t0, y0, p)
            start = self.c.loop_minors(t0, y0, p)[k]
            watched.append(((lambda t, y, k=k: self.c.loop_minors(t, y, p)[k]),
                            -math.copysign(1, start), "minor", k))
        return watched

    def _loop_singular(self, t, y, p):
        """Raise the named error of a loop singularity at a state."""
        from .assembly import _independent_text
        raise LoopSingularError(_weakest_constraint(self.c, t, y, p), t, y,
                                f" ({_independent_text(self.c, y)})")

    def _drifted(self, t, y, p):
        """True when the loops' positions or speeds have drifted beyond the tolerance
        (rtol times the loops' size): the segment ends there and the state is projected."""
        position, speed = self.c.drift(t, y, p)
        size = self._loop_size
        return position > self.scene.rtol * size or \
            speed > self.scene.rtol * size * self._speed_scale

    # ------------------------------------------------------------------ driver
    def execute(self, y0) -> Result:
        t, t_limit = self.scene.t_start, self.scene.time_limit
        y = np.array(y0, dtype=float)
        for i, stop in enumerate(self.c.stops):
            if stop(t, y, self.base + [0.0] * self.k) == 0:
                raise SceneError(f"scene {self.scene.name!r}: stop condition "
                                 f"{self.c.stop_labels[i]} is already met at the start")
        started = time.perf_counter()
        reason = "t_end"
        try:
            mode = self._decide(t, y)
            y = self._project(t, y, mode)
            while True:
                outcome = self._segment(mode, t, y, t_limit)
                if outcome is None:
                    break
                t, y, fired = outcome
                kinds = {kind for kind, _ in fired}
                if "minor" in kinds and np.max(np.abs(self.c.loop_minors(
                        t, y, self.base + mode.signs))) < LOOP_MARGIN * self._minor_scale:
                    self._loop_singular(t, y, self.base + mode.signs)  # ... all at once
                    # (else one minor passed zero at a regular position: a new segment
                    # watches the largest minor there)
                if "drift" in kinds:          # closed loops: back onto the constraints
                    y = project(self.c, t, y, self.base + mode.signs)
                    self.trajectory.replace_last_state(y)
                    self.stats["projections"] = self.stats.get("projections", 0) + 1
                stops = [i for kind, i in fired if kind == "stop"]
                frictions = [(kind, i) for kind, i in fired if kind in ("stick", "release")]
                if frictions:
                    signs, released = list(mode.signs), {}
                    for kind, i in frictions:
                        if kind == "release":
                            _, lam, _ = self._constrained(t, y, self.base + mode.signs,
                                                          mode.stuck)
                            released[i] = -math.copysign(1.0, lam[mode.stuck.index(i)])
                        signs[i] = 0.0
                    y = self._project(t, y, _Mode(signs))
                    mode = self._decide(t, y, released)
                    for kind, i in frictions:
                        if kind == "stick" and i in mode.stuck:
                            self.events.append(Event(t, "stick", self.c.frictions[i],
                                                     "sliding stopped, held by friction"))
                    y = self._project(t, y, mode)
                    self.trajectory.replace_last_state(y)
                if stops:
                    reason = self.c.stop_labels[stops[0]]
                    self.events.append(Event(t, "end", reason, "stop condition met"))
                    break
        except SimulationError as error:
            self.stats["wall_time"] = time.perf_counter() - started
            error.partial = self._result("failed: " + str(error))
            if not str(error).startswith("integration"):
                error.args = (f"integration failed: {error}",)
            raise
        if reason == "t_end" and self.c.stops:
            reason = "t_end (stop condition not reached)"
        self.stats["wall_time"] = time.perf_counter() - started
        return self._result(reason)

    def _segment(self, mode, t0, y0, t_limit):
        """Integrate one mode from ``t0`` until an event or the time limit.

        Returns ``(t, y, fired)`` at an event, ``None`` at the time limit."""
        if t0 >= t_limit:
            return None
        raw_fun, jac, p = self._functions(mode)
        fun = _tolerant(raw_fun, (2 * self.n,))
        jac = _tolerant(jac, (2 * self.n, 2 * self.n)) if jac is not None else None
        watched = self._event_functions(mode, p, t0, y0)
        if self.c.constraints:
            _, loop_grads, _, _ = closure_parts(self.c, t0, y0, p)
            self._loop_size = float(np.max(np.abs(loop_grads)))
            self._speed_scale = 1.0 + float(np.max(np.abs(y0[self.n:])))
        self._mass_scale = float(np.max(np.abs(self._terms(t0, y0, p)[0])))
        rtol, atol = self.scene.rtol, self.atol
        self.stats["segments"] += 1
        segment = self.trajectory.start_segment(t0, y0, mode.signs, mode.stuck,
                                                (self.method, fun, jac, rtol, atol))
        state = {"g": [w[0](t0, y0) for w in watched], "fired": None}

        def on_step(t_old, y_old, t, y, dense):
            if not np.all(np.isfinite(y)):
                raise SimulationError(f"integration failed at t = {t:.6g} s: the state "
                                      f"became non-finite ({self._state_text(y)})")
            g_new = [w[0](t, y) for w in watched]
            fired = self._locate(watched, state["g"], g_new, dense, t_old, t)
            if fired:
                t_event, indices, interpolant = fired
                y_event = interpolant(t_event)
                segment.add(t_event, y_event)
                state["fired"] = (t_event, y_event,
                                  [(watched[i][2], watched[i][3]) for i in indices])
                return True
            segment.add(t, y)
            state["g"] = g_new
            if self.c.constraints and self._drifted(t, y, p):
                state["fired"] = (t, y, [("drift", 0)])
                return True
            return False
        try:
            status, message, t, y, counts = run_steps(self.method, fun, jac, t0, y0,
                                                      t_limit, rtol, atol, on_step)
        except (ArithmeticError, ValueError) as error:
            raise SimulationError(
                f"integration failed near t = {segment.t[-1]:.6g} s: {type(error).__name__}: "
                f"{error} while evaluating the events at state "
                f"{self._state_text(segment.y[-1])}") from error
        self._count(counts)
        if status == "failed":
            raise SimulationError(f"integration failed at t = {t:.6g} s: {message}; state "
                                  f"{self._state_text(y)}" + _evaluation_fault(raw_fun, t, y)
                                  + self._singularity_hint(t, y, p))
        return state["fired"]

    @staticmethod
    def _locate(watched, g_old, g_new, make_dense, t_old, t_new):
        """The earliest event in the step, every event at that same instant, and the
        step's interpolant (built only when an event must be located)."""
        roots, dense = [], None
        for i, ((function, direction, _, _), a, b) in enumerate(zip(watched, g_old, g_new)):
            crossed = (a < 0 <= b) if direction > 0 else (a > 0 >= b)
            if a == 0 or not crossed:
                continue
            dense = dense or make_dense()
            if b == 0:
                root = t_new
            else:
                root = brentq(lambda s: function(s, dense(s)), t_old, t_new,
                              xtol=4 * _EPS, rtol=4 * _EPS)
            roots.append((root, i))
        if not roots:
            return None
        first = min(r for r, _ in roots)
        same = 1e-12 * max(1.0, abs(first))
        return first, [i for r, i in roots if r - first <= same], dense

    def _count(self, counts):
        """Add a finished segment's solver counts to the run's statistics."""
        for key, value in counts.items():
            self.stats[key] += value

    def _singularity_hint(self, t, y, p) -> str:
        """Why steps collapse, when it is a nearly singular mass matrix (a dead centre)."""
        try:
            mass = self._terms(t, y, p)[0]
            eigenvalues = np.linalg.eigvalsh(mass)
        except (ArithmeticError, ValueError, np.linalg.LinAlgError):
            return ""
        scale = max(abs(eigenvalues[-1]), self._mass_scale)
        if eigenvalues[0] > 1e-9 * scale:
            return ""
        return (f". The mass matrix is nearly singular there (smallest eigenvalue "
                f"{eigenvalues[0]:.3g} of {eigenvalues[-1]:.3g}): the reduced inertia of "
                f"{', '.join(self.c.coordinates)} vanishes at this configuration, a dead "
                "centre of the chosen coordinate")

    def _state_text(self, y):
        return ", ".join(f"{name} = {value:.6g}" for name, value in zip(self.c.state_names, y))

    def _result(self, reason) -> Result:
        return Result(self.c, self.trajectory, self.events, reason, dict(self.stats),
                      self.base, self.scene, self.mechanism_name, self.units, self)


def _weakest_constraint(compiled, t, y, p):
    """The constraint most nearly dependent on the others (the loop that locks)."""
    _, grads, _, _ = closure_parts(compiled, t, y, p)
    scaled = grads / np.linalg.norm(grads, axis=1, keepdims=True)
    residuals = []
    for k in range(len(scaled)):
        others = np.delete(scaled, k, axis=0)
        if not len(others):
            residuals.append(np.linalg.norm(scaled[k]))
            continue
        fit = np.linalg.lstsq(others.T, scaled[k], rcond=None)[0]
        residuals.append(np.linalg.norm(scaled[k] - others.T @ fit))
    return compiled.meta["loops"][int(np.argmin(residuals))]


def _parallel_groups(grads, stuck):
    """Stuck frictions grouped by parallel gradients: lists of ``(index, alpha)`` with
    ``grads[index] = alpha * grads[first of group]``."""
    groups = []
    for k in stuck:
        g = grads[k]
        for members in groups:
            reference = grads[members[0][0]]
            alpha = float(g @ reference) / float(reference @ reference)
            if np.linalg.norm(g - alpha * reference) <= 1e-12 * np.linalg.norm(g):
                members.append((k, alpha))
                break
        else:
            groups.append([(k, 1.0)])
    return groups


_EVALUATION_ERRORS = (ArithmeticError, ValueError, SimulationError, np.linalg.LinAlgError)


def _tolerant(function, shape):
    """``function`` as the solver should see it: NaN where the equations cannot be
    evaluated (an overflowing trial stage, a singular mass matrix there), so the step is
    rejected and shrunk as for any NaN. Real failures surface as a collapsing step size."""
    failed = np.full(shape, np.nan)

    def guarded(t, y):
        try:
            return function(t, y)
        except _EVALUATION_ERRORS:
            return failed
    return guarded


def _evaluation_fault(function, t, y) -> str:
    """Why the equations cannot be evaluated at a state, if they cannot."""
    try:
        values = np.asarray(function(t, y), dtype=float)
    except _EVALUATION_ERRORS as error:
        return f". The equations cannot be evaluated there: {type(error).__name__}: {error}"
    if not np.all(np.isfinite(values)):
        return ". The equations give non-finite values there (overflow or division by zero)"
    return ""
