"""Kinematic analysis of closed-loop linkages: positions by Newton's method, transmission
functions by implicit differentiation, reduced inertia and moment along the crank angle.

A :class:`Linkage` compiles a mechanism's loop constraints, mass matrix and generalized
forces (numbers for the parameters given) and walks the independent coordinate: each
position is solved by Newton's method with the analytic constraint Jacobian, warm-started
from the previous one with a second-order predictor (``q + q' d phi + q'' d phi^2 / 2``),
and the step is halved where Newton fails or the solution jumps, so one assembly branch
is kept, through change points too (:mod:`mechdyn.analyse.linkage_walk`). Speeds and accelerations follow by implicit differentiation
(:mod:`mechdyn.derive.transmission`): ``q' = S``, ``G_d q_d'' = -bias(q, q')``.

>>> import sympy as sp, mechdyn as md
>>> phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
>>> four = md.Mechanism("four-bar", [phi, th2, th3])
>>> _ = four.link("crank", J=1, angle=phi)
>>> _ = four.link("coupler", J=1, angle=th2)
>>> _ = four.link("rocker", J=1, angle=th3)
>>> _ = four.loop("ABCD", (1, phi), (3, th2), (-2.5, th3), (-3, 0))
>>> linkage = md.Linkage(four, guess={th2: 1, th3: 2})
>>> q = linkage.position(0.0)                 # open assembly at phi = 0
>>> [round(float(v), 8) for v in q]
[0.0, 0.97338991, 1.69612416]
>>> linkage.grashof().kind
'crank-rocker'
"""
from __future__ import annotations

import numpy as np

from mechdyn.analyse.linkage_types import (CrankSweep, Grashof, LinkageError, Singularity,
                                           grashof)
from mechdyn.compile.linkage_code import LinkageFunctions
from mechdyn.declare.elements import Constraint
from mechdyn.symbols import is_coordinate, t

__all__ = ["Linkage", "LinkageError", "CrankSweep", "Singularity", "Grashof", "grashof"]


class Linkage:
    """Numeric kinematics of a mechanism with closed loops.

    Parameters
    ----------
    mechanism : Mechanism
        With loops (:meth:`~mechdyn.Mechanism.loop`) and at least one dependent coordinate.
    params : dict, optional
        Parameter values (all that the loops, masses and loads use).
    guess : dict, optional
        Values of the dependent coordinates near the wanted assembly (the branch);
        default: the scene's initial values, else zero.
    scene : Scene, optional
        Selects the loads for the reduced moment; its initial values are the guess.
    guess_at : float or sequence, optional
        The independent coordinate(s) the guess belongs to (default: those in ``guess``,
        else the scene's initial values, else zero): the linkage is assembled there.

    Raises
    ------
    LinkageError
        No loops or no dependent coordinate, or loops that cannot be closed near the
        guess.

    Examples
    --------
    A crank-rocker (ground 3, crank 1, coupler 3, rocker 2.5):

    >>> import mechdyn as md
    >>> phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    >>> four = md.Mechanism("four-bar", [phi, th2, th3])
    >>> _ = four.link("crank", J=1, angle=phi)
    >>> _ = four.link("coupler", J=1, angle=th2)
    >>> _ = four.link("rocker", J=1, angle=th3)
    >>> _ = four.loop("ABCD", (1, phi), (3, th2), (-2.5, th3), (-3, 0))
    >>> linkage = md.Linkage(four, guess={th2: 1, th3: 2})
    >>> [round(float(v), 8) for v in linkage.position(0.0)]
    [0.0, 0.97338991, 1.69612416]
    >>> linkage.grashof().crank_turns
    True
    """

    def __init__(self, mechanism, params=None, guess=None, scene=None, guess_at=None):
        from mechdyn.declare.parameters import ParameterSet
        self.mechanism = mechanism
        values = ParameterSet(params, mechanism=mechanism, scene=scene)  # before deriving
        self.eqs = eqs = mechanism.equations(scene)
        if not eqs.constraints:
            raise LinkageError(f"{mechanism.name!r} has no loops; declare them with "
                               "mech.loop(...) or mech.constraint(...)")
        if any(t in c.expression.free_symbols for c in eqs.constraints):
            raise LinkageError(f"{mechanism.name!r}: the loops depend on time; the kinematic "
                               "analysis needs loops of the coordinates alone")
        self.names = tuple(str(q) for q in eqs.q)
        self.n, self.m = eqs.dof, len(eqs.constraints)
        self.independent = [eqs.q.index(q) for q in eqs.independent]
        self.dependent = [i for i in range(self.n) if i not in self.independent]
        self.functions = LinkageFunctions(eqs)
        self.p = self.functions.parameter_vector(values)
        self.params = dict(values)
        self._last = self._start(guess, scene, guess_at)

    # ------------------------------------------------------------- positions
    def _start(self, guess, scene, guess_at):
        q = np.zeros(self.n)
        values = dict(scene.initial) if scene is not None else {}
        values.update(guess or {})
        for key, value in values.items():
            name = key.func.__name__ if is_coordinate(key) else str(key)
            if name in self.names:
                q[self.names.index(name)] = float(value)
        if guess_at is not None:
            at = np.atleast_1d(np.asarray(guess_at, dtype=float))
            if at.shape != (len(self.independent),) or not np.all(np.isfinite(at)):
                raise LinkageError(f"guess_at = {guess_at!r}: give one finite value for "
                                   "each independent coordinate ("
                                   f"{', '.join(self.names[i] for i in self.independent)})")
            q[self.independent] = at
        return q

    def closure(self, q):
        """``(g, G)``: the loop residuals and their Jacobian at the positions ``q``."""
        v = self.functions.closure(0.0, np.concatenate([q, np.zeros(self.n)]), self.p)
        return np.array(v[:self.m]), np.array(v[self.m:]).reshape(self.m, self.n)

    def position(self, phi):
        """All coordinates at the independent value(s) ``phi``, continued from the last
        position solved (the branch is kept). Raises :class:`LinkageError` where the
        loops cannot be closed."""
        target = np.atleast_1d(np.asarray(phi, dtype=float))
        q, reached = self._walk(self._last, target)
        if q is None:
            raise LinkageError(
                f"{self.mechanism.name!r}: the loops cannot be closed at "
                f"{self._independent_text(target)}; the linkage reaches only "
                f"{self._independent_text(reached)} on this branch (a toggle position: "
                "see singularities(), crank_range())", at=float(target[0]))
        self._last = q
        return q

    # -------------------------------------------------------------- derivatives
    def velocity_matrix(self, q):
        """``S`` (n x k) at the closed positions ``q``: ``u = S u_i`` (by implicit
        differentiation: at a change point, where the loops do not determine it, use
        :meth:`derivatives`, :meth:`state` or :meth:`sweep`: the limits along the
        branch)."""
        _, grads = self.closure(q)
        k = len(self.independent)
        matrix = np.zeros((self.n, k))
        matrix[self.independent, range(k)] = 1.0
        matrix[self.dependent] = -np.linalg.solve(grads[:, self.dependent],
                                                  grads[:, self.independent])
        return matrix

    def reduced_mass_matrix(self, q):
        """``S' M S`` (k x k) at the closed positions ``q``: the mass matrix of the
        independent coordinates (``I_red`` for one)."""
        matrix = self.velocity_matrix(q)
        y = np.concatenate([q, np.zeros(self.n)])
        mass = np.array(self.functions.mass(0.0, y, self.p)).reshape(self.n, self.n)
        return matrix.T @ mass @ matrix

    def _second(self, q, ratio):
        """``d2q/dphi2`` from ``G_d q_d'' = -bias(q, q')`` (independent: zero)."""
        _, grads = self.closure(q)
        bias = self.functions.bias(0.0, np.concatenate([q, ratio]), self.p)
        out = np.zeros(self.n)
        out[self.dependent] = -np.linalg.solve(grads[:, self.dependent], bias)
        return out

    def state(self, phi, omega, eps=0.0):
        """Positions, speeds and accelerations of all coordinates for the crank at
        ``phi`` turning at ``omega`` with acceleration ``eps`` (one-DOF)."""
        q = self.position(phi)
        ratio, second = self.derivatives(q)
        return q, ratio * omega, ratio * eps + second * omega ** 2

    def sweep(self, phi) -> CrankSweep:
        """Positions, transmission functions and reduced inertia at each crank angle
        of ``phi`` (walked in the given order, one branch kept)."""
        self._one_dof("sweep")
        phi = np.asarray(phi, dtype=float)
        q = np.zeros((self.n, len(phi)))
        ratio, second = np.zeros_like(q), np.zeros_like(q)
        inertia, slope = np.zeros(len(phi)), np.zeros(len(phi))
        for j, value in enumerate(phi):
            q[:, j] = self.position(value)
            ratio[:, j], second[:, j] = self.derivatives(q[:, j])
            inertia[j], slope[j] = self._inertia(q[:, j], ratio[:, j], second[:, j])
        return CrankSweep(phi, q, ratio, second, inertia, slope, self.names)

    def _inertia(self, q, ratio, second):
        """``I_red = S'MS`` and ``I_red' = 2 (S' M q'' - S' f_in(q, S))``."""
        y = np.concatenate([q, ratio])
        mass = np.array(self.functions.mass(0.0, y, self.p)).reshape(self.n, self.n)
        inertial = np.array(self.functions.inertial(0.0, y, self.p))
        return ratio @ mass @ ratio, 2 * (ratio @ mass @ second - ratio @ inertial)

    def reduced_inertia(self, phi):
        """``I_red`` at the crank angle(s) ``phi`` (a number or an array)."""
        values = self.sweep(np.atleast_1d(phi)).inertia
        return float(values[0]) if np.ndim(phi) == 0 else values

    def reduced_inertia_slope(self, phi):
        """``dI_red/dphi`` at the crank angle(s) ``phi``."""
        values = self.sweep(np.atleast_1d(phi)).inertia_slope
        return float(values[0]) if np.ndim(phi) == 0 else values

    def reduced_moment(self, phi, omega=0.0, t_value=0.0, exclude=()):
        """``M_red = S' Q`` at the crank angle(s) ``phi`` and crank speed ``omega``,
        without the loads named in ``exclude`` (friction elements are left out)."""
        self._one_dof("reduced_moment")
        out = []
        for value in np.atleast_1d(phi):
            q = self.position(value)
            ratio = self.velocity_matrix(q)[:, 0]
            columns = self.functions.forces(t_value, np.concatenate([q, ratio * omega]),
                                            self.p)
            out.append(sum(ratio @ np.array(column) for name, column in
                           zip(self.functions.force_names, columns) if name not in exclude))
        return float(out[0]) if np.ndim(phi) == 0 else np.array(out)

    # --------------------------------------------------------------- helpers
    def evaluate(self, expressions, sweep: CrankSweep, speeds=None):
        """Expressions of the coordinates (and speeds, with ``speeds``: an array like
        ``sweep.q``) at every position of a sweep, one row per expression."""
        compiled = self.functions.expressions(list(expressions))
        u = np.zeros_like(sweep.q) if speeds is None else speeds
        return np.array([compiled(0.0, np.concatenate([sweep.q[:, j], u[:, j]]), self.p)
                         for j in range(len(sweep.phi))]).T

    def _one_dof(self, what):
        if len(self.independent) != 1:
            raise LinkageError(f"{what}: {self.mechanism.name!r} has "
                               f"{len(self.independent)} independent coordinates; analyse "
                               "it with position() and velocity_matrix()")

    def _independent_text(self, values):
        return ", ".join(f"{self.names[i]} = {v:.6g} ({np.degrees(v):.2f} deg)"
                         for i, v in zip(self.independent, np.atleast_1d(values)))

    def loop_of(self, row):
        """The loop element a scalar constraint (row of G) belongs to."""
        label = self.eqs.constraints[row].name
        for name, element in self.mechanism.elements.items():
            if isinstance(element, Constraint) and label in element.labels:
                return name
        return label

    def plot(self, path=None, points=361, paths=None):
        """Transmission functions, ``I_red`` and its slope, the transmission angle and
        the paths of ``paths`` (name -> point ``(x, y)``: coupler curves) over a crank
        revolution (:func:`mechdyn.analyse.linkage_plots.plot_linkage`)."""
        from mechdyn.analyse.linkage_plots import plot_linkage
        return plot_linkage(self, path, points, paths)

    # The continuation and the analyses in their own modules, bound here.
    from mechdyn.analyse.linkage_walk import (_newton, _predict, _walk,  # noqa: E402
                                              derivatives, margin)
    from mechdyn.analyse.linkage_limits import (coupler_curve, crank_range,  # noqa: E402
                                 extremes, grashof, singularities, transmission_angle)
    from mechdyn.analyse.linkage_describe import describe  # noqa: E402
