"""Steady running of a one-DOF machine and the flywheel that evens its speed.

A machine whose reduced inertia ``I(phi)`` and reduced moment ``M(phi, omega)`` repeat
over a cycle ``Phi`` of its coordinate (a crank turn, ``2 pi``; a four-stroke engine,
``4 pi``) runs steadily when its speed repeats: ``omega(phi0 + Phi) = omega(phi0)``.
With the crank angle as the independent variable the equation of motion
``d(I omega^2 / 2)/dphi = M`` reads

    d omega/dphi = a(phi, omega) / omega,   dt/dphi = 1 / omega

(``a`` the angular acceleration from the compiled equations). Shooting finds
``omega0``: Newton's method on ``omega(phi0 + Phi) - omega0``, its derivative ``v`` from
the variational equation ``dv/dphi = d(a/omega)/domega v`` (analytic Jacobian). ``v``
over one cycle is the Floquet multiplier of the cycle map: ``|v| < 1`` stable. One
cycle is integrated by :mod:`mechdyn.analyse.cycle_map` (on the compiled kernels where
the scene runs there, as ``simulate`` does).

Mean speed ``omega_mean = Phi / t_cycle`` (time average), coefficient of speed
fluctuation ``delta = (omega_max - omega_min) / omega_mean``. :func:`flywheel` solves
``delta(J) = target`` for a flywheel parameter ``J`` (brentq on ``log J``) and compares
with the textbook ``J = Delta E_max / (delta omega_mean^2)``, ``Delta E_max`` the largest
swing of the excess work ``W(phi) = integral (M(phi, omega_mean) - mean M) dphi``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from scipy.integrate import cumulative_trapezoid, trapezoid
from scipy.optimize import brentq, minimize_scalar

from mechdyn.compile.compiler import compile_scene
from mechdyn.errors import SceneError
from mechdyn.declare.parameters import ParameterSet, missing_values
from mechdyn.analyse.shooting import Floquet, PeriodicError
from mechdyn.analyse.cycle_map import RTOL as _RTOL, CycleMap
from mechdyn.symbols import t

__all__ = ["SteadyRunning", "Flywheel", "steady_running", "flywheel", "applies"]

_MAX_NEWTON = 40
_POINTS = 4001


def applies(mechanism, scene) -> bool:
    """True for a one-DOF scene whose equations do not depend on the time ``t``."""
    eqs = mechanism.equations(scene)
    exprs = [eqs.mass_matrix[0, 0], eqs.smooth_forcing[0]] if eqs.dof == 1 else []
    return bool(exprs) and not any(t in e.free_symbols for e in exprs)


@dataclass(frozen=True)
class SteadyRunning:
    """One cycle of steady running.

    Attributes: ``phi`` (grid over the cycle), ``omega`` and ``time`` on it, ``cycle``
    (rad), ``cycle_time`` (s), ``omega_mean`` (``cycle / cycle_time``), ``omega_max``,
    ``omega_min``, ``delta`` (coefficient of speed fluctuation), ``floquet`` (the cycle
    map's multiplier), ``name`` (mechanism and scene); ``outputs_at(phi)`` the scene's
    outputs over the cycle. ``repr`` is a one-line summary, ``summary()`` a few lines.

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi, J = md.coordinate("phi"), sp.Symbol("J", positive=True)
    >>> machine = md.Mechanism("machine", [phi])
    >>> _ = machine.link("crank and flywheel", J=J, angle=phi)
    >>> _ = machine.load("motor", md.motors.dc_shunt(400, 110)(md.speed(phi)), along=phi)
    >>> _ = machine.load("process", 20 * sp.cos(phi), along=phi)
    >>> scene = md.Scene("run", initial={phi: 0, md.speed(phi): 100}, t_end=1)
    >>> running = md.steady_running(machine, scene, {J: 2})
    >>> round(running.omega_max - running.omega_min, 3)     # delta * omega_mean
    0.182
    """
    phi: np.ndarray
    omega: np.ndarray
    time: np.ndarray
    cycle: float
    cycle_time: float
    omega_max: float
    omega_min: float
    floquet: Floquet
    name: str
    compiled: object = field(default=None, repr=False, compare=False)
    p: list = field(default=None, repr=False, compare=False)
    dense: object = field(default=None, repr=False, compare=False)   # phi -> [omega, t, v]

    @property
    def omega_mean(self) -> float:
        return self.cycle / self.cycle_time

    @property
    def delta(self) -> float:
        return (self.omega_max - self.omega_min) / self.omega_mean

    @property
    def initial(self) -> tuple:
        """``(phi0, omega0)``: the periodic state at the start of the cycle."""
        return float(self.phi[0]), float(self.omega[0])

    @property
    def steps(self) -> np.ndarray:
        """The angles of the integrator's steps over the cycle."""
        return np.asarray(self.dense.ts, dtype=float)

    def outputs_at(self, phi) -> dict:
        """The scene's outputs (label -> array) at the angles ``phi`` of the cycle."""
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        states = self.dense(phi)
        values = np.array([self.compiled.outputs(states[1][j], (x, states[0][j]), self.p)
                           for j, x in enumerate(phi)]).reshape(len(phi), -1)
        return {label: values[:, k] for k, label in enumerate(self.compiled.output_labels)}

    def __repr__(self):
        return (f"<SteadyRunning {self.name}: omega_mean = {self.omega_mean:.6g} rad/s, "
                f"delta = {self.delta:.6g}, cycle {self.cycle:.6g} rad in "
                f"{self.cycle_time:.6g} s>")

    def summary(self) -> str:
        phi0, omega0 = self.initial
        return "\n".join([
            f"{self.name}: steady running over a cycle of {self.cycle:.6g} rad",
            f"  periodic state at phi = {phi0:.6g} rad: omega = {omega0:.9g} rad/s",
            f"  mean speed {self.omega_mean:.6g} rad/s (cycle time {self.cycle_time:.6g} s); "
            f"omega max {self.omega_max:.6g}, min {self.omega_min:.6g} rad/s",
            f"  coefficient of speed fluctuation delta = {self.delta:.6g} "
            f"(1/{1 / self.delta:.4g})" if self.delta > 0 else "  delta = 0",
            f"  {self.floquet}"])

    def plot(self, path=None):
        """omega(phi) over the cycle with its mean, maximum and minimum."""
        from mechdyn.plotting import finish, pyplot
        plt = pyplot()
        fig, ax = plt.subplots(figsize=(8, 3.6))
        ax.plot(self.phi, self.omega, label="omega(phi)")
        for value, style, label in ((self.omega_mean, "-", "mean"),
                                    (self.omega_max, "--", "max"),
                                    (self.omega_min, "--", "min")):
            ax.axhline(value, color="grey", ls=style, lw=0.8, label=f"{label} {value:.5g}")
        ax.set_xlabel("phi [rad]")
        ax.set_ylabel("omega [rad/s]")
        ax.set_title(f"{self.name}: delta = {self.delta:.4g}")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        return finish(fig, path)


def _check(mechanism, scene, params):
    """The scene's equations and the checked parameter values (checked before the
    equations are derived)."""
    from mechdyn.declare.scene import Scene
    if not isinstance(scene, Scene):
        raise SceneError(f"steady running needs a md.Scene, got {scene!r}")
    if scene.until:
        raise SceneError(f"scene {scene.name!r} stops at "
                         f"{', '.join(map(repr, scene.until))}: a run that ends at a stop "
                         "condition has no periodic regime to find; use a scene without until=")
    values = ParameterSet(params, mechanism=mechanism, scene=scene)
    eqs = mechanism.equations(scene)
    if eqs.switching:
        raise PeriodicError(f"scene {scene.name!r}: Coulomb friction, stops or one-way "
                            f"elements ({', '.join(eqs.switching)}) are not smooth; "
                            "leave them out of the scene's effects")
    if not applies(mechanism, scene):
        raise PeriodicError(
            f"scene {scene.name!r}: steady running in the crank angle needs one coordinate "
            f"and equations free of the time t ({eqs.name!r} has {eqs.dof} coordinates"
            f"{'' if eqs.dof != 1 else ' and depends on t'}); use md.periodic_steady_state")
    return eqs, values


def steady_running(mechanism, scene, params, cycle=2 * math.pi, *,
                   speed_guess=None) -> SteadyRunning:
    """The periodic speed ``omega(phi)`` of a one-DOF machine over one cycle.

    Parameters
    ----------
    mechanism, scene, params
        As for ``mechanism.simulate``; one coordinate, equations free of ``t``, no stop
        condition. The cycle starts at the scene's initial angle.
    cycle : float
        ``Phi`` in rad, over which ``I_red`` and ``M_red`` repeat.
    speed_guess : float, optional
        First guess of the speed at the cycle's start (default: the scene's initial
        speed, which must then be positive).

    Returns
    -------
    SteadyRunning

    Raises
    ------
    PeriodicError
        Friction, stops or one-way elements in the scene, several coordinates or a time
        dependence, no convergence.

    Examples
    --------
    A shunt motor ``400 (1 - omega/110)`` against a process moment ``20 cos(phi)`` on a
    flywheel ``J``:

    >>> import sympy as sp, mechdyn as md
    >>> phi, J = md.coordinate("phi"), sp.Symbol("J", positive=True)
    >>> machine = md.Mechanism("machine", [phi])
    >>> _ = machine.link("crank and flywheel", J=J, angle=phi)
    >>> _ = machine.load("motor", md.motors.dc_shunt(400, 110)(md.speed(phi)), along=phi)
    >>> _ = machine.load("process", 20 * sp.cos(phi), along=phi)
    >>> scene = md.Scene("run", initial={phi: 0, md.speed(phi): 100}, t_end=1)
    >>> running = md.steady_running(machine, scene, {J: 2})
    >>> round(running.omega_mean, 3)       # the motor balances at 110 (1 - 0) = 110 rad/s
    110.0
    >>> round(running.delta, 4)            # 2 A / (omega sqrt((J omega)^2 + b^2)), b = 400/110
    0.0017
    """
    eqs, values = _check(mechanism, scene, params)
    cycle = float(cycle)
    if not (math.isfinite(cycle) and cycle > 0):
        raise PeriodicError(f"cycle = {cycle} must be positive and finite")
    compiled = compile_scene(mechanism, scene)
    p = compiled.parameter_vector(values)
    phi0, omega0 = _start(compiled, mechanism, scene, values.numbers, speed_guess)
    cycle_map = CycleMap(compiled, scene, p)
    tolerance = 1e3 * _RTOL
    for _ in range(_MAX_NEWTON):
        omega, v, cycle_time, dense = cycle_map(phi0, cycle, omega0)
        residual = omega - omega0
        if abs(residual) <= 100 * _RTOL * omega0:
            break
        if abs(v - 1) < tolerance:
            raise PeriodicError(
                f"scene {scene.name!r}: the cycle map's multiplier is 1 (no speed-dependent "
                "moment fixes the mean speed) and the speed does not repeat: the machine "
                "speeds up or slows down cycle after cycle")
        step = -residual / (v - 1)
        omega0 = omega0 + step if omega0 + step > 0 else omega0 / 2
    else:
        raise PeriodicError(f"scene {scene.name!r}: no steady running found in "
                            f"{_MAX_NEWTON} Newton steps (last speed {omega0:.6g} rad/s)")
    phi = np.linspace(phi0, phi0 + cycle, _POINTS)
    states = dense(phi)
    high = _extreme(dense, phi, states[0], -1)
    low = _extreme(dense, phi, states[0], 1)
    return SteadyRunning(phi, states[0], states[1], cycle, float(cycle_time), high, low,
                         Floquet.of([[v]], cycle_time, tolerance, over=f"one cycle "
                                    f"({cycle:.6g} rad)"),
                         f"{eqs.name} — scene {scene.name!r}", compiled, p, dense)


def _start(compiled, mechanism, scene, params, speed_guess):
    from mechdyn.simulate.simulation import initial_state
    y0 = initial_state(compiled, mechanism, scene, params)
    omega0 = y0[1] if speed_guess is None else float(speed_guess)
    if not omega0 > 0:
        raise PeriodicError(f"scene {scene.name!r}: the first guess of the steady speed is "
                            f"{omega0:.6g} rad/s; give a positive initial speed near the "
                            "steady one (or speed_guess=; mechdyn periodic --speed-guess)")
    return float(y0[0]), float(omega0)


def _extreme(dense, grid, values, sign):
    """The minimum of ``sign * omega`` on the dense output, polished near the grid's."""
    k = int(np.argmin(sign * values))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    best = minimize_scalar(lambda x: sign * dense(x)[0], bounds=(lo, hi), method="bounded",
                           options={"xatol": 1e-12 * max(1.0, abs(hi))})
    return float(min(sign * values[k], best.fun) * sign)


@dataclass(frozen=True)
class Flywheel:
    """A flywheel sized for a coefficient of speed fluctuation.

    Attributes: ``parameter`` (symbol), ``inertia`` (its value giving ``target``),
    ``target``, ``running`` (:class:`SteadyRunning` with it), ``energy_swing``
    (``Delta E_max``, J), ``textbook`` (``Delta E_max / (delta omega_mean^2)`` turned into
    the parameter's value: less the machine's own mean reduced inertia, divided by the
    parameter's coefficient in ``I_red``), ``own_inertia`` (mean ``I_red`` without the
    flywheel).

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> phi, J = md.coordinate("phi"), sp.Symbol("J", positive=True)
    >>> machine = md.Mechanism("machine", [phi])
    >>> _ = machine.link("crank and flywheel", J=J, angle=phi)
    >>> _ = machine.load("motor", md.motors.dc_shunt(400, 110)(md.speed(phi)), along=phi)
    >>> _ = machine.load("process", 20 * sp.cos(phi), along=phi)
    >>> scene = md.Scene("run", initial={phi: 0, md.speed(phi): 100}, t_end=1)
    >>> sized = md.flywheel(machine, scene, {J: 2}, delta=0.01, inertia=J)
    >>> sized.parameter, sized.target, round(sized.energy_swing, 3)   # Delta E_max = 2 A
    (J, 0.01, 40.0)
    """
    parameter: sp.Symbol
    inertia: float
    target: float
    running: SteadyRunning
    energy_swing: float
    textbook: float
    own_inertia: float

    def __repr__(self):
        return (f"<Flywheel {self.parameter} = {self.inertia:.6g} for delta = "
                f"{self.target:.6g} (textbook {self.textbook:.6g})>")

    def summary(self) -> str:
        return "\n".join([
            f"flywheel {self.parameter} = {self.inertia:.6g} for delta = {self.target:.6g} "
            f"(steady running gives {self.running.delta:.6g})",
            f"  textbook Delta E_max / (delta omega_mean^2): {self.parameter} = "
            f"{self.textbook:.6g} (Delta E_max = {self.energy_swing:.6g} J, omega_mean = "
            f"{self.running.omega_mean:.6g} rad/s, own mean I_red {self.own_inertia:.6g})"])


def flywheel(mechanism, scene, params, delta, inertia, cycle=2 * math.pi, *,
             speed_guess=None) -> Flywheel:
    """The value of the flywheel parameter ``inertia`` that brings the coefficient of
    speed fluctuation to ``delta``, and the textbook estimate.

    Parameters
    ----------
    mechanism, scene, params, cycle
        As for :func:`steady_running`; ``params`` gives a starting value of ``inertia``.
    delta : float
        Target coefficient of speed fluctuation, ``0 < delta < 1``.
    inertia : sympy.Symbol
        A parameter entering ``I_red`` linearly with a constant positive coefficient
        (a flywheel's moment of inertia on the crank or a geared shaft).
    speed_guess : float, optional
        As for :func:`steady_running`: the first guess of the first steady speed.

    Returns
    -------
    Flywheel

    Examples
    --------
    The machine of :func:`steady_running`, ``J w w' = 400 (1 - w/110) + 20 cos(phi)``,
    needs ``J = 0.3289`` for ``delta = 2 A / (w sqrt((J w)^2 + b^2)) = 0.01``
    (linearised); the textbook ``Delta E_max = 2 A = 40 J`` gives
    ``40 / (0.01 * 110^2) = 0.3306``:

    >>> import sympy as sp, mechdyn as md
    >>> phi, J = md.coordinate("phi"), sp.Symbol("J", positive=True)
    >>> machine = md.Mechanism("machine", [phi])
    >>> _ = machine.link("crank and flywheel", J=J, angle=phi)
    >>> _ = machine.load("motor", md.motors.dc_shunt(400, 110)(md.speed(phi)), along=phi)
    >>> _ = machine.load("process", 20 * sp.cos(phi), along=phi)
    >>> scene = md.Scene("run", initial={phi: 0, md.speed(phi): 100}, t_end=1)
    >>> sized = md.flywheel(machine, scene, {J: 2}, delta=0.01, inertia=J)
    >>> round(sized.inertia, 4), round(sized.textbook, 4)
    (0.3289, 0.3306)
    """
    eqs, values = _check(mechanism, scene, params)
    if not 0 < float(delta) < 1:
        raise PeriodicError(f"delta = {delta} must lie between 0 and 1")
    params = values.numbers
    key = str(inertia)
    if key not in params:
        raise missing_values([key], "flywheel sizing (its starting value)", mechanism.name)
    inertia = next((s for s in eqs.reduced_inertia.free_symbols if s.name == key), None)
    if inertia is None:
        raise PeriodicError(f"flywheel: {key} does not enter the reduced inertia "
                            f"{eqs.reduced_inertia}")
    coefficient = values.substitute(sp.diff(eqs.reduced_inertia, inertia))
    if not (coefficient.is_number and coefficient > 0) or \
            sp.diff(eqs.reduced_inertia, inertia, 2) != 0:
        raise PeriodicError(f"flywheel: {inertia} must enter the reduced inertia "
                            f"{eqs.reduced_inertia} linearly with a constant positive "
                            f"coefficient (it enters as {sp.diff(eqs.reduced_inertia, inertia)})")
    coefficient = float(coefficient)
    guess = {"speed": speed_guess}

    def running_with(value):
        result = steady_running(mechanism, scene, params | {key: value}, cycle,
                                speed_guess=guess["speed"])
        guess["speed"] = result.initial[1]
        return result

    def mismatch(log_value):
        return math.log(running_with(math.exp(log_value)).delta / delta)
    start = float(params[key])
    if not start > 0:
        raise PeriodicError(f"flywheel: the starting value {inertia} = {start} must be positive")
    near, f_near = math.log(start), mismatch(math.log(start))
    step = math.log(2) if f_near > 0 else -math.log(2)      # delta too large: more flywheel
    far, f_far = near + step, mismatch(near + step)
    for _ in range(60):
        if f_near * f_far <= 0:
            break
        near, f_near = far, f_far
        far, f_far = far + step, mismatch(far + step)
    else:
        raise PeriodicError(f"flywheel: no value of {inertia} brings delta to {delta}")
    value = math.exp(brentq(mismatch, min(near, far), max(near, far), xtol=1e-9))
    running = running_with(value)
    swing, own = _textbook_terms(eqs, params | {key: 0.0}, running)
    textbook = (swing / (delta * running.omega_mean ** 2) - own) / coefficient
    return Flywheel(inertia, value, float(delta), running, swing, textbook, own)


def _textbook_terms(eqs, params, running):
    """``Delta E_max`` from ``M_red(phi, omega_mean)``, and the mean ``I_red`` of
    ``params`` (the flywheel set to zero) over the cycle."""
    values = ParameterSet(params)

    def numeric(expr):
        expr = values.substitute(expr)
        return np.broadcast_to(sp.lambdify((eqs.q[0], eqs.u[0]), expr, "numpy")(
            running.phi, running.omega_mean), running.phi.shape)
    moment = numeric(eqs.reduced_moment)
    work = cumulative_trapezoid(moment - trapezoid(moment, running.phi) / running.cycle,
                                running.phi, initial=0.0)
    inertia = numeric(eqs.reduced_inertia)
    return float(work.max() - work.min()), float(trapezoid(inertia, running.phi) /
                                                 running.cycle)
