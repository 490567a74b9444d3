"""Shooting for periodic motion: the problem set up from a scene (forcing period,
guess, tolerances), the flow and its monodromy matrix, Newton on ``y(T) - y0``, and the
Floquet multipliers (see :mod:`mechdyn.analyse.periodic`)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import scipy.linalg
import sympy as sp
from scipy.integrate import solve_ivp

from mechdyn.compile.compiler import compile_scene
from mechdyn.errors import MechdynError, SceneError
from mechdyn.declare.parameters import ParameterSet, missing_values
from mechdyn.symbols import t

__all__ = ["Floquet", "PeriodicError", "NoPeriodicSolutionError", "forcing_period"]

_RTOL = {"explicit": 1e-10, "implicit": 1e-8}   # default rtol by the kind of method
_IMPLICIT = ("Radau", "BDF", "LSODA")
_UNIT = 1e3            # a multiplier within _UNIT * rtol of a value counts as equal to it
_MAX_NEWTON = 30


class PeriodicError(MechdynError, ValueError):
    """A periodic analysis that cannot be done (bad period, no convergence, friction).

    Examples
    --------
    Steady running needs smooth equations; a brake switches:

    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> phi = model.mechanism.coordinates[0]
    >>> run = md.Scene("run", initial={phi: 0, md.speed(phi): 100}, t_end=1)
    >>> try:
    ...     md.steady_running(model.mechanism, run, model.params)
    ... except md.PeriodicError as error:
    ...     print(type(error).__name__)
    PeriodicError
    """


class NoPeriodicSolutionError(PeriodicError):
    """A Floquet multiplier equals 1: the periodic motion is not unique or does not exist.
    ``floquet`` holds the multipliers.

    Examples
    --------
    An undamped oscillator forced at its natural frequency (resonance):

    >>> import sympy as sp, mechdyn as md
    >>> x = md.coordinate("x")
    >>> oscillator = md.Mechanism("resonant oscillator", [x])
    >>> _ = oscillator.link("mass", m=1, x=x)
    >>> _ = oscillator.spring("spring", 1, stretch=x)
    >>> _ = oscillator.load("force", sp.cos(md.t), along=x)
    >>> try:
    ...     md.periodic_steady_state(oscillator, md.Scene("steady", t_end=1), {})
    ... except md.NoPeriodicSolutionError as error:
    ...     print(error.floquet.multipliers.round(6))
    [1. 1.]
    """

    def __init__(self, message, floquet):
        super().__init__(message)
        self.floquet = floquet


@dataclass(frozen=True)
class Floquet:
    """Floquet multipliers: eigenvalues of the monodromy matrix over one period.

    Attributes: ``multipliers`` (by decreasing modulus), ``monodromy``, ``period`` (s),
    ``tolerance`` (a modulus within it of 1 counts as 1), ``over`` (what one period is).

    Examples
    --------
    The multipliers of the damped oscillator ``x'' + 0.4 x' + 4 x = 0`` over the period
    ``2 pi`` have the modulus ``exp(-0.2 * 2 pi)``:

    >>> import sympy as sp, mechdyn as md
    >>> x = md.coordinate("x")
    >>> oscillator = md.Mechanism("oscillator", [x])
    >>> _ = oscillator.link("mass", m=1, x=x)
    >>> _ = oscillator.spring("spring", 4, stretch=x)
    >>> _ = oscillator.damper("damper", 0.4, stretch=x)
    >>> multipliers = md.floquet(oscillator, md.Scene("free", t_end=1), {}, period=2 * sp.pi)
    >>> abs(multipliers.multipliers).round(6), round(float(sp.exp(-0.4 * sp.pi)), 6)
    (array([0.28461, 0.28461]), 0.28461)
    """
    multipliers: np.ndarray
    monodromy: np.ndarray
    period: float
    tolerance: float
    over: str = "one period"

    @classmethod
    def of(cls, monodromy, period, tolerance, over="one period") -> "Floquet":
        """The multipliers of ``monodromy``, by decreasing modulus (real when none has an
        imaginary part beyond ``tolerance``)."""
        monodromy = np.atleast_2d(np.asarray(monodromy, dtype=float))
        values = np.linalg.eigvals(monodromy)
        values = values[np.argsort(-np.abs(values), kind="stable")]
        if np.all(np.abs(values.imag) <= tolerance * np.maximum(1.0, np.abs(values))):
            values = values.real
        return cls(values, monodromy, float(period), float(tolerance), over)

    @property
    def spectral_radius(self) -> float:
        """The largest modulus ``max |mu|``."""
        return float(np.max(np.abs(self.multipliers)))

    @property
    def exponents(self) -> np.ndarray:
        """Floquet exponents ``log(mu) / T`` (real part: growth rate per second)."""
        return np.log(self.multipliers.astype(complex)) / self.period

    @property
    def stable(self) -> bool:
        """True when every ``|mu| < 1``: disturbances die out (asymptotic stability)."""
        return self.spectral_radius < 1 - self.tolerance

    @property
    def verdict(self) -> str:
        """'asymptotically stable', 'unstable', or 'on the stability boundary' (the
        largest ``|mu|`` is 1 within the tolerance: bounded but not decaying, as an
        undamped system, unless multipliers on the unit circle coincide)."""
        if self.stable:
            return "asymptotically stable"
        if self.spectral_radius > 1 + self.tolerance:
            return "unstable"
        return "on the stability boundary"

    def __repr__(self):
        return (f"<Floquet over {self.over}: max |mu| = {self.spectral_radius:.6g}, "
                f"{self.verdict}>")

    def __str__(self):
        values = ", ".join(_complex_text(m) for m in self.multipliers)
        return (f"Floquet multipliers over {self.over}: {values} "
                f"(max |mu| = {self.spectral_radius:.6g}): {self.verdict}")


def _complex_text(value) -> str:
    value = complex(value)
    if value.imag == 0:
        return f"{value.real:.6g}"
    return f"{value.real:.6g}{value.imag:+.6g}j"


@dataclass(frozen=True)
class _Problem:
    """A compiled scene ready for periodic analysis."""
    mechanism: object
    scene: object
    params: dict
    compiled: object
    p: list
    t0: float
    period: float
    linear: bool
    guess: np.ndarray
    method: str
    rtol: float
    atol: float

    @property
    def tolerance(self) -> float:
        return _UNIT * self.rtol


def forcing_period(mechanism, scene, params) -> float:
    """The common period of the explicit time dependence of a scene's equations.

    Every ``t`` must sit in a ``sin`` or ``cos`` whose argument is ``omega_k t`` plus
    terms free of ``t``, with commensurate ``omega_k``: ``T = 2 pi / gcd(omega_k)``.

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> x = md.coordinate("x")
    >>> shaker = md.Mechanism("shaker", [x])
    >>> _ = shaker.link("mass", m=1, x=x)
    >>> _ = shaker.spring("spring", 2 + sp.cos(3 * md.t), stretch=x)
    >>> _ = shaker.load("force", sp.sin(2 * md.t), along=x)
    >>> round(md.forcing_period(shaker, None, {}), 9)     # gcd(3, 2) = 1
    6.283185307
    """
    values = ParameterSet(params, mechanism=mechanism, scene=scene)
    eqs = mechanism.equations(scene)
    exprs = list(eqs.mass_matrix) + list(eqs.smooth_forcing)
    trig = {f for e in exprs for f in e.atoms(sp.sin, sp.cos) if t in f.free_symbols}
    rest = [e.xreplace({f: sp.Dummy() for f in trig}) for e in exprs]
    if any(t in e.free_symbols for e in rest):
        raise PeriodicError(f"{eqs.name!r}: cannot infer the period: the equations depend "
                            "on t other than through sin and cos; give the period "
                            "(period=T; on the command line --period T)")
    if not trig:
        raise PeriodicError(f"{eqs.name!r}: cannot infer the period: the equations do not "
                            "depend on t; give the period (period=T; on the command line "
                            "--period T)")
    rates = []
    for f in trig:
        rate = sp.diff(f.args[0], t)
        number = values.substitute(rate)
        if t in rate.free_symbols:
            raise PeriodicError(f"{eqs.name!r}: cannot infer the period from {f} (its "
                                "argument is not omega*t plus terms free of t); give period=T")
        if not number.is_number:
            raise missing_values(sorted(s.name for s in number.free_symbols),
                                 f"the period of {f}", eqs.name)
        if number != 0:
            rates.append(abs(float(number)))
    base = min(rates)
    fractions = [Fraction(r / base).limit_denominator(64) for r in rates]
    if any(abs(float(fr) - r / base) > 1e-9 * r / base for fr, r in zip(fractions, rates)):
        raise PeriodicError(f"{eqs.name!r}: the time dependence has incommensurate "
                            f"frequencies {sorted(set(rates))} rad/s (quasi-periodic, no "
                            "common period)")
    numerator = math.gcd(*(fr.numerator for fr in fractions))
    denominator = math.lcm(*(fr.denominator for fr in fractions))
    return 2 * math.pi * denominator / (base * numerator)


def _period_value(period, values, mechanism, scene) -> float:
    """``T`` from ``period`` (a number or an expression of parameters) with the checked
    parameter ``values``, or inferred from the equations."""
    if period is None:
        return forcing_period(mechanism, scene, values)
    if isinstance(period, sp.Basic):
        period = values.substitute(period)
    try:
        value = float(period)
    except (TypeError, ValueError):
        raise PeriodicError(f"period = {period!r} is not a number") from None
    if not (math.isfinite(value) and value > 0):
        raise PeriodicError(f"period = {value} must be positive and finite")
    return value


def _is_linear(eqs) -> bool:
    """Symbolic, conservative: M free of q, every df/dx free of the state x = [q, u]."""
    state = set(eqs.q) | set(eqs.u)
    if any(e.free_symbols & state for e in eqs.mass_matrix):
        return False
    return not any(sp.diff(f, x).free_symbols & state
                   for f in eqs.smooth_forcing for x in (*eqs.q, *eqs.u))


def _guess(compiled, mechanism, scene, params) -> np.ndarray:
    """The scene's initial state as the first guess (zeros where it gives none)."""
    from mechdyn.simulate.simulation import initial_state
    try:
        return initial_state(compiled, mechanism, scene, params)
    except SceneError:
        return np.zeros(len(compiled.state_names))


def _problem(mechanism, scene, params, period, rtol, atol) -> _Problem:
    from mechdyn.simulate.methods import choose_method
    from mechdyn.simulate.stepping import METHODS
    from mechdyn.declare.scene import Scene
    if not isinstance(scene, Scene):
        raise SceneError(f"a periodic analysis needs a md.Scene, got {scene!r}")
    if scene.until:
        labels = ", ".join(map(repr, scene.until))
        raise SceneError(f"scene {scene.name!r} stops at {labels}: a run that ends at a "
                         "stop condition has no periodic regime to find; use a scene "
                         "without until=")
    values = ParameterSet(params, mechanism=mechanism, scene=scene)   # before deriving
    eqs = mechanism.equations(scene)
    if eqs.switching:
        raise PeriodicError(f"scene {scene.name!r}: Coulomb friction, stops or one-way "
                            f"elements ({', '.join(eqs.switching)}) switch between "
                            "modes; the periodic analysis needs smooth equations (leave "
                            "them out of the scene's effects)")
    params = values.numbers
    T = _period_value(period, values, mechanism, scene)
    compiled = compile_scene(mechanism, scene)
    p = compiled.parameter_vector(values)
    guess = _guess(compiled, mechanism, scene, params)
    _check_budget(compiled, p, guess, scene, T)
    method = scene.method
    if method == "auto":
        method, _ = choose_method(compiled, p, guess, scene.t_start, scene.t_start + T,
                                  _RTOL["explicit"])
    elif method not in METHODS:
        raise SceneError(f"scene {scene.name!r}: unknown method {method!r}")
    if rtol is None:
        rtol = _RTOL["implicit" if method in _IMPLICIT else "explicit"]
    atol = rtol * 1e-2 if atol is None else atol
    return _Problem(mechanism, scene, dict(params), compiled, p, scene.t_start, T,
                    _is_linear(eqs), guess, method, rtol, atol)


def _check_budget(compiled, p, y, scene, T):
    """Refuse up front a period far longer than the motion's fastest time scale allows
    within the scene's step budget (``--period 1e300`` would integrate for minutes and
    then fail): the scale is the shortest forcing period and the fastest oscillation
    of the linearised motion at the start (the largest imaginary part of the Jacobian's
    eigenvalues; stiff decay is left to implicit methods), each step covering at most
    one radian of it."""
    budget = scene.max_steps
    if budget is None:
        return
    periods = [0.0] * compiled.meta["periods"]
    compiled.raw["periods"](scene.t_start, [0.0] * len(y), p, periods)
    try:
        rate = float(np.max(np.abs(np.linalg.eigvals(compiled.jac(scene.t_start, y, p))
                                   .imag), initial=0.0))
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        rate = 0.0
    rates = [rate] + [2 * math.pi / period for period in periods if period > 0]
    steps = T * max(rates)
    if steps > budget:
        raise PeriodicError(
            f"period = {T:.6g} s is about {steps:.3g} radians of the motion's fastest "
            f"time scale ({1 / max(rates):.3g} s): more than the scene's step budget "
            f"max_steps = {budget:,} allows; give the period of one cycle (or a larger "
            "max_steps)")


def _integrate(problem, fun, z0, jac):
    options = {"method": problem.method, "rtol": problem.rtol, "atol": problem.atol}
    if problem.method in _IMPLICIT:
        options["jac"] = jac
    try:
        sol = solve_ivp(fun, (problem.t0, problem.t0 + problem.period), z0, **options)
    except (ArithmeticError, ValueError) as error:
        raise PeriodicError(f"integration over one period failed: {type(error).__name__}: "
                            f"{error}") from error
    if sol.status != 0:
        raise PeriodicError(f"integration over one period failed: {sol.message}")
    return sol


def _initial_parameters(problem):
    """``K(T)`` (columns: solutions from the unit vectors) and ``Y_p(T)`` (from zero)."""
    c, p = problem.compiled, problem.p
    m = len(c.state_names)
    zero = np.zeros(m)

    def fun(time, z):
        out = np.array([c.rhs(time, row, p) for row in z.reshape(m + 1, m)])
        out[1:] -= np.asarray(c.rhs(time, zero, p))
        return out.ravel()

    def jac(time, z):
        return np.kron(np.eye(m + 1), c.jac(time, zero, p))
    end = _integrate(problem, fun, np.vstack([zero, np.eye(m)]).ravel(), jac).y[:, -1]
    rows = end.reshape(m + 1, m)
    return rows[1:].T, rows[0]


def _flow(problem, y0):
    """``y(t0 + T)``, the monodromy ``Phi(T)`` and each state's largest magnitude."""
    c, p = problem.compiled, problem.p
    m = len(y0)

    def fun(time, z):
        a = c.jac(time, z[:m], p)
        return np.concatenate([c.rhs(time, z[:m], p), (a @ z[m:].reshape(m, m)).ravel()])

    def jac(time, z):          # drops d(J Phi)/dy: exact for linear systems, fine for Newton
        a = c.jac(time, z[:m], p)
        return scipy.linalg.block_diag(a, np.kron(a, np.eye(m)))
    sol = _integrate(problem, fun, np.concatenate([y0, np.eye(m).ravel()]), jac)
    return sol.y[:m, -1], sol.y[m:, -1].reshape(m, m), np.abs(sol.y[:m]).max(axis=1)


def _check_unique(problem, monodromy):
    multipliers = Floquet.of(monodromy, problem.period, problem.tolerance)
    distance = float(np.min(np.abs(multipliers.multipliers - 1)))
    if distance < problem.tolerance:
        raise NoPeriodicSolutionError(
            f"scene {problem.scene.name!r}: a Floquet multiplier equals 1 within the "
            f"integration accuracy (|mu - 1| = {distance:.2e} < {problem.tolerance:.0e}; "
            f"multipliers {', '.join(_complex_text(m) for m in multipliers.multipliers)}): "
            f"over T = {problem.period:.6g} s the periodic motion is not unique or does "
            "not exist (forcing in resonance with an undamped motion of that period, or a "
            "free rigid-body motion). md.floquet gives the multipliers alone", multipliers)


def _shoot(problem):
    """Newton on ``y(T) - y0``; returns ``(y0, monodromy, iterations)``."""
    y0 = np.array(problem.guess, dtype=float)
    for iteration in range(_MAX_NEWTON + 1):
        end, monodromy, scale = _flow(problem, y0)
        residual = end - y0
        if np.all(np.abs(residual) <= 100 * (problem.rtol * scale + problem.atol)):
            return y0, monodromy, iteration
        if iteration == _MAX_NEWTON:
            break
        _check_unique(problem, monodromy)
        y0 = y0 + np.linalg.solve(monodromy - np.eye(len(y0)), -residual)
        if not np.all(np.isfinite(y0)):
            break
    raise PeriodicError(f"scene {problem.scene.name!r}: shooting did not converge in "
                        f"{_MAX_NEWTON} Newton steps (largest residual "
                        f"{np.max(np.abs(residual)):.3g}); start the scene nearer the "
                        "periodic motion (initial=...)")


def _method(problem, method) -> str:
    if method not in ("auto", "initial parameters", "shooting"):
        raise PeriodicError(f"method {method!r}: use 'auto', 'initial parameters' or "
                            "'shooting'")
    if method == "auto":
        return "initial parameters" if problem.linear else "shooting"
    if method == "initial parameters" and not problem.linear:
        raise PeriodicError(f"scene {problem.scene.name!r}: the method of initial "
                            "parameters needs equations linear in the state; these are "
                            "not (use method='shooting')")
    return method


