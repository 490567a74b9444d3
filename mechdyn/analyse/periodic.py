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

from dataclasses import replace
import numpy as np
from mechdyn.symbols import dotted_symbol, speed
from mechdyn.analyse.shooting import (Floquet, _check_unique, _initial_parameters, _method, _problem, _shoot)

__all__ = ["PeriodicSolution", "periodic_steady_state", "floquet"]


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
    mechdyn.analyse.shooting.NoPeriodicSolutionError: scene 'steady': a Floquet multiplier equals 1 ...
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

    Examples
    --------
    A damped oscillator ``x'' + 0.4 x' + 4 x = cos(t)`` (the module's example):

    >>> import sympy as sp, mechdyn as md
    >>> x = md.coordinate("x")
    >>> oscillator = md.Mechanism("forced oscillator", [x])
    >>> _ = oscillator.link("mass", m=1, x=x)
    >>> _ = oscillator.spring("spring", 4, stretch=x)
    >>> _ = oscillator.damper("damper", 0.4, stretch=x)
    >>> _ = oscillator.load("force", sp.cos(md.t), along=x)
    >>> steady = md.periodic_steady_state(oscillator, md.Scene("steady", t_end=1), {})
    >>> steady.state_names, steady.y0.round(6)          # 3/9.16, 0.4/9.16
    (['x', 'xdot'], array([0.327511, 0.043668]))
    >>> float(steady.closure) < 1e-8
    True
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
