"""Steady periodic motion under periodic forcing and parametric excitation; Floquet
multipliers.

A scene whose equations ``M(q, t) q'' = f(q, q', t)`` repeat after a period ``T`` has a
periodic motion when its state ``y = [q, u]`` comes back after one period,
``y(t0 + T) = y(t0)``. Two ways to find that initial state:

* **Method of initial parameters** (systems linear in the state,
  ``y' = A(t) y + b(t)``): the fundamental matrix ``K(T)`` from the ``2n`` unit initial
  vectors (homogeneous solutions by superposition, ``k' = rhs(t, k) - rhs(t, 0)``) and
  the particular solution ``Y_p`` from the zero state, integrated together; then
  ``(I - K(T)) C = Y_p(T)``.
* **Shooting** (any smooth system): Newton's method on ``y(t0 + T) - y0``, the monodromy
  matrix from the variational equations ``Phi' = J(t, y) Phi`` with the compiled
  analytic Jacobian ``J``.

Linearity is decided symbolically and conservatively: the system counts as linear when
the mass matrix does not depend on the coordinates and no derivative of the forcing
with respect to a coordinate or speed depends on a coordinate or speed. An expression
that only looks nonlinear (a parameter that would cancel a term) goes to shooting,
which also solves a linear system (in one Newton step).

Integration: ``solve_ivp`` with the scene's method (``auto``: DOP853, or Radau when the
Jacobian shows the scene stiff, given the block Jacobian ``diag(J, J, ...)``, exact for
linear systems); rtol 1e-10 for explicit methods, 1e-8 for implicit ones.

The Floquet multipliers are the eigenvalues of the monodromy matrix (``K(T)``, or the
variational matrix along the periodic motion): all ``|mu| < 1`` is asymptotically
stable, one ``|mu| > 1`` unstable. A multiplier at 1 (within the integration accuracy,
``1e3 * rtol``) leaves the periodic motion undetermined: :class:`NoPeriodicSolutionError`.

The period may be left out when the explicit time dependence consists of sines and
cosines of ``omega_k t + ...`` with commensurate ``omega_k``: ``T = 2 pi / gcd(omega_k)``.

>>> import sympy as sp, mechdyn as md
>>> x = md.coordinate("x")
>>> oscillator = md.Mechanism("forced oscillator", [x])
>>> _ = oscillator.link("mass", m=1, x=x)
>>> _ = oscillator.spring("spring", 4, stretch=x)
>>> _ = oscillator.damper("damper", 0.4, stretch=x)
>>> _ = oscillator.load("force", sp.cos(md.t), along=x)
>>> steady = md.periodic_steady_state(oscillator, md.Scene("steady", t_end=1), {})
>>> round(steady.period, 6), steady.method
(6.283185, 'initial parameters')
>>> round(steady.initial["x"], 6), round(steady.initial["xdot"], 6)  # 3/9.16, 0.4/9.16
(0.327511, 0.043668)
>>> steady.floquet.verdict
'asymptotically stable'
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from fractions import Fraction

import numpy as np
import scipy.linalg
import sympy as sp
from scipy.integrate import solve_ivp

from mechdyn.compile.compiler import compile_scene
from mechdyn.errors import MechdynError, SceneError
from mechdyn.declare.parameters import ParameterSet
from mechdyn.symbols import dotted_symbol, speed, t

__all__ = ["Floquet", "PeriodicSolution", "PeriodicError", "NoPeriodicSolutionError",
           "periodic_steady_state", "floquet", "forcing_period"]

_RTOL = {"explicit": 1e-10, "implicit": 1e-8}   # default rtol by the kind of method
_IMPLICIT = ("Radau", "BDF", "LSODA")
_UNIT = 1e3            # a multiplier within _UNIT * rtol of a value counts as equal to it
_MAX_NEWTON = 30


class PeriodicError(MechdynError, ValueError):
    """A periodic analysis that cannot be done (bad period, no convergence, friction)."""


class NoPeriodicSolutionError(PeriodicError):
    """A Floquet multiplier equals 1: the periodic motion is not unique or does not exist.
    ``floquet`` holds the multipliers."""

    def __init__(self, message, floquet):
        super().__init__(message)
        self.floquet = floquet


@dataclass(frozen=True)
class Floquet:
    """Floquet multipliers: eigenvalues of the monodromy matrix over one period.

    Attributes: ``multipliers`` (by decreasing modulus), ``monodromy``, ``period`` (s),
    ``tolerance`` (a modulus within it of 1 counts as 1), ``over`` (what one period is).
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

    >>> import sympy as sp, mechdyn as md
    >>> x = md.coordinate("x")
    >>> shaker = md.Mechanism("shaker", [x])
    >>> _ = shaker.link("mass", m=1, x=x)
    >>> _ = shaker.spring("spring", 2 + sp.cos(3 * md.t), stretch=x)
    >>> _ = shaker.load("force", sp.sin(2 * md.t), along=x)
    >>> round(md.forcing_period(shaker, None, {}), 9)     # gcd(3, 2) = 1
    6.283185307
    """
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
        number = _substitute(rate, params)
        if t in rate.free_symbols or not number.is_number:
            raise PeriodicError(f"{eqs.name!r}: cannot infer the period from {f} (its "
                                "argument is not omega*t plus terms free of t, or a parameter "
                                "has no value); give period=T")
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


def _substitute(expr, params):
    """``expr`` with the parameter values (keys: symbols or names) put in."""
    return ParameterSet(params).substitute(expr)


def _period_value(period, params, mechanism, scene) -> float:
    if period is None:
        return forcing_period(mechanism, scene, params)
    if isinstance(period, sp.Basic):
        period = _substitute(period, params)
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
    eqs = mechanism.equations(scene)
    if eqs.switching:
        raise PeriodicError(f"scene {scene.name!r}: Coulomb friction, stops or one-way "
                            f"elements ({', '.join(eqs.switching)}) switch between "
                            "modes; the periodic analysis needs smooth equations (leave "
                            "them out of the scene's effects)")
    values = ParameterSet(params, mechanism=mechanism, scene=scene)
    params = values.numbers
    T = _period_value(period, params, mechanism, scene)
    compiled = compile_scene(mechanism, scene)
    p = compiled.parameter_vector(values)
    guess = _guess(compiled, mechanism, scene, params)
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


def floquet(mechanism, scene, params, period=None, *, method="auto", rtol=None,
            atol=None) -> Floquet:
    """Floquet multipliers of a scene over one period, whatever their values.

    Linear systems: the eigenvalues of the fundamental matrix ``K(T)`` (independent of
    any forcing). Nonlinear ones: of the monodromy matrix along the periodic motion
    found by shooting.

    Parameters
    ----------
    mechanism, scene, params
        As for ``mechanism.simulate``; the scene must have no stop condition.
    period : float or sympy expression of parameters, optional
        ``T``; inferred from the sines and cosines of ``t`` when left out.
    method : {'auto', 'initial parameters', 'shooting'}
    rtol, atol : float, optional
        Integration tolerances; default rtol 1e-10 (explicit methods) or 1e-8 (Radau,
        BDF, LSODA: stiff scenes), atol rtol/100.

    Examples
    --------
    Mathieu's equation ``x'' + (1/4 + 0.1 cos t) x = 0``, inside the first instability
    tongue: the multipliers' product is 1 (no damping), one has ``|mu| > 1``.

    >>> import sympy as sp, mechdyn as md
    >>> x = md.coordinate("x")
    >>> mathieu = md.Mechanism("Mathieu", [x])
    >>> _ = mathieu.link("mass", m=1, x=x)
    >>> _ = mathieu.spring("spring", sp.Rational(1, 4) + sp.cos(md.t) / 10, stretch=x)
    >>> mu = md.floquet(mathieu, md.Scene("free", t_end=1), {}, period=2 * sp.pi)
    >>> round(float(np.prod(mu.multipliers)), 9), mu.verdict
    (1.0, 'unstable')
    """
    problem = _problem(mechanism, scene, params, period, rtol, atol)
    if _method(problem, method) == "initial parameters":
        monodromy, _ = _initial_parameters(problem)
    else:
        _, monodromy, _ = _shoot(problem)
    return Floquet.of(monodromy, problem.period, problem.tolerance)


def periodic_steady_state(mechanism, scene, params, period=None, *, method="auto",
                          rtol=None, atol=None) -> "PeriodicSolution":
    """The periodic motion of a periodically forced or excited scene.

    Parameters
    ----------
    mechanism, scene, params
        As for ``mechanism.simulate``; the scene's initial state is the first guess of
        shooting; it must have no stop condition.
    period : float or sympy expression of parameters, optional
        ``T``; inferred from the sines and cosines of ``t`` when left out.
    method : {'auto', 'initial parameters', 'shooting'}
        'auto': initial parameters for systems linear in the state, else shooting.
    rtol, atol : float, optional
        Integration tolerances, as for :func:`floquet`.

    Returns
    -------
    PeriodicSolution

    Raises
    ------
    NoPeriodicSolutionError
        A Floquet multiplier is 1 within ``1e3 * rtol``.

    Examples
    --------
    >>> import sympy as sp, mechdyn as md
    >>> x = md.coordinate("x")
    >>> osc = md.Mechanism("resonant oscillator", [x])
    >>> _ = osc.link("mass", m=1, x=x)
    >>> _ = osc.spring("spring", 1, stretch=x)
    >>> _ = osc.load("force", sp.cos(md.t), along=x)
    >>> md.periodic_steady_state(osc, md.Scene("steady", t_end=1), {})
    Traceback (most recent call last):
    ...
    mechdyn.analyse.periodic.NoPeriodicSolutionError: scene 'steady': a Floquet multiplier equals 1 ...
    """
    problem = _problem(mechanism, scene, params, period, rtol, atol)
    chosen = _method(problem, method)
    if chosen == "initial parameters":
        monodromy, particular = _initial_parameters(problem)
        _check_unique(problem, monodromy)
        y0 = np.linalg.solve(np.eye(len(particular)) - monodromy, particular)
        iterations = 0
    else:
        y0, monodromy, iterations = _shoot(problem)
    multipliers = Floquet.of(monodromy, problem.period, problem.tolerance)
    return PeriodicSolution(problem, y0, multipliers, chosen, iterations)


class PeriodicSolution:
    """A periodic motion: its initial state, one period as a :class:`~mechdyn.Result`,
    and its Floquet multipliers.

    Attributes: ``period`` (s), ``t0`` (start of the period), ``state_names``,
    ``initial`` (state name -> value at ``t0``), ``y0`` (the same as an array), ``floquet`` (:class:`Floquet`),
    ``method`` ('initial parameters' or 'shooting'), ``iterations`` (Newton steps),
    ``linear`` (the symbolic verdict), ``result`` (one period integrated from ``y0``),
    ``closure`` (largest ``|y(t0 + T) - y0|`` of that run).
    """

    def __init__(self, problem, y0, multipliers, method, iterations):
        self._problem = problem
        self.period, self.t0 = problem.period, problem.t0
        self.state_names = list(problem.compiled.state_names)
        self.y0 = np.asarray(y0, dtype=float)
        self.initial = dict(zip(self.state_names, map(float, self.y0)))
        self.floquet, self.method, self.iterations = multipliers, method, iterations
        self.linear = problem.linear
        self.result = self._one_period()
        self.closure = float(np.max(np.abs(self.result.y[:, -1] - self.y0)))

    def _one_period(self):
        problem = self._problem
        coordinates = {q.func.__name__: q for q in problem.mechanism.coordinates}
        names = problem.compiled.coordinates
        n = len(names)
        initial = {}
        for i, name in enumerate(names):
            initial[coordinates[name]] = self.y0[i]
            initial[speed(coordinates[name])] = self.y0[n + i]
        scene = problem.scene
        atol = min(scene.atol, problem.atol) if not isinstance(scene.atol, dict) else scene.atol
        scene = replace(scene, initial=initial, until=(), t_end=self.t0 + self.period,
                        rtol=min(scene.rtol, problem.rtol), atol=atol)
        return problem.mechanism.simulate(scene, problem.params)

    def at(self, time) -> dict:
        """The state (name -> value) at ``time``, the motion repeated periodically."""
        shifted = self.t0 + (float(time) - self.t0) % self.period
        return self.result.at(shifted)

    def extremes(self, points=2001) -> dict:
        """``(min, max)`` over one period of every state and acceleration (named as in
        ``Result.columns``: ``phi_2``, ``phidot_2``, ``phiddot_2``), on ``points`` times."""
        c, p = self._problem.compiled, self._problem.p
        times = np.linspace(self.t0, self.t0 + self.period, points)
        states = self.result.trajectory.at(times)
        n = c.dof
        accelerations = np.array([c.rhs(s, states[:, j], p)[n:]
                                  for j, s in enumerate(times)]).T
        names = self.state_names + [str(dotted_symbol(q, 2)) for q in c.coordinates]
        rows = np.vstack([states, accelerations])
        return {name: (float(row.min()), float(row.max())) for name, row in zip(names, rows)}

    def amplitudes(self, points=2001) -> dict:
        """Half the peak-to-peak swing of every state and acceleration over one period."""
        return {name: (high - low) / 2 for name, (low, high) in self.extremes(points).items()}

    def summary(self) -> str:
        """The periodic state, the swing of every state and acceleration, the multipliers."""
        how = (f"{self.method}" + (f", {self.iterations} Newton steps" if
                                   self.method == "shooting" else ""))
        r = self.result
        lines = [f"{r.mechanism_name} — scene {r.scene.name!r}: periodic motion, "
                 f"T = {self.period:.6g} s ({how}; "
                 f"{'linear' if self.linear else 'nonlinear'} in the state)",
                 f"  state at t = {self.t0:.6g} s: " + ", ".join(
                     f"{k} = {v:.6g}" for k, v in self.initial.items()),
                 f"  {'':12s} {'min':>13s} {'max':>13s} {'amplitude':>13s}"]
        for name, (low, high) in self.extremes().items():
            lines.append(f"  {name:12s} {low:13.6g} {high:13.6g} {(high - low) / 2:13.6g}")
        lines.append(f"  {self.floquet}")
        lines.append(f"  closure |y(t0 + T) - y(t0)| = {self.closure:.2e}")
        return "\n".join(lines)

    def plot(self, path=None):
        """States and outputs over one period (see ``Result.plot``)."""
        return self.result.plot(path)

    def __repr__(self):
        return (f"<PeriodicSolution T = {self.period:.6g} s, {self.method}, "
                f"max |mu| = {self.floquet.spectral_radius:.6g}>")
