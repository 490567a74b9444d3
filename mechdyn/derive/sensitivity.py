"""The forward sensitivity equations of ``M(q, p) q'' = f(q, q', t, p)``, derived with
sympy from the same equations the simulation integrates.

With the state ``y = [q, u]`` and ``S = dy/dp`` the sensitivities obey
``S' = [[0, I], [da/dq, da/du]] S + [0; da/dp]``, where the accelerations' derivatives
follow from differentiating ``M a = f`` without inverting ``M`` symbolically:

    M da/dz = d(f - M a)/dz      (a held fixed),   z = q, u or p

so :class:`ForwardEquations` holds ``M``, ``f`` and the residual's Jacobian ``R =
d(f - M a)/d[q, u, p]`` in the symbols ``a`` (the accelerations, solved for at run time).
Sliding friction enters with its sign fixed (``sign``: +1 or -1 per element), as in the
compiled right-hand side. :func:`cycle_equations` gives the same for steady running in
the crank angle, ``d omega/d phi = h = a / omega``.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> J, M = sp.symbols("J M", positive=True)
>>> disc = md.Mechanism("disc", [phi])
>>> _ = disc.link("disc", J=J, angle=phi)
>>> _ = disc.load("drive", M, along=phi)
>>> forward = forward_equations(disc.equations(), [J, M])
>>> forward.residual_jacobian       # d(M - J a)/d[phi, phidot, J, M]
Matrix([[0, 0, -phiddot, 1]])
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from mechdyn.symbols import t

__all__ = ["ForwardEquations", "forward_equations", "cycle_equations", "signed_forcing",
           "stop_derivatives"]


@dataclass(frozen=True)
class ForwardEquations:
    """``mass`` ``M`` (n x n), ``forcing`` ``f`` (n), ``residual_jacobian``
    ``d(f - M a)/d[q, u, p]`` (n x (2n + len(p))) in ``q``, ``u``, ``a``, ``t`` and the
    parameters; ``wrt`` the parameters differentiated for."""
    q: tuple
    u: tuple
    a: tuple
    wrt: tuple
    mass: sp.Matrix
    forcing: sp.Matrix
    residual_jacobian: sp.Matrix


def signed_forcing(eqs, signs=None) -> sp.Matrix:
    """The forcing with each sliding friction pushing ``-sign * magnitude`` along its
    gradient (``signs``: +1/-1 per friction element; ``|rate|`` in a magnitude written
    ``sign * rate``)."""
    forcing = eqs.smooth_forcing
    for friction, sign in zip(eqs.frictions, signs or ()):
        rate = friction.rate
        magnitude = friction.magnitude.xreplace({sp.Abs(rate): sign * rate,
                                                 sp.Abs(-rate): sign * rate})
        forcing = forcing - sign * magnitude * friction.gradient
    return forcing


def forward_equations(eqs, wrt, signs=None, replace=None) -> ForwardEquations:
    """The sensitivity equations of ``eqs`` with respect to the symbols ``wrt``.

    ``replace``: ``{symbol: expression}`` put in first (parameters given as expressions
    of the ones differentiated for, so the chain rule is exact)."""
    replace = replace or {}
    mass = eqs.mass_matrix.xreplace(replace)
    forcing = signed_forcing(eqs, signs).xreplace(replace)
    a = sp.Matrix(eqs.a)
    residual = forcing - mass * a
    variables = list(eqs.q) + list(eqs.u) + list(wrt)
    return ForwardEquations(tuple(eqs.q), tuple(eqs.u), tuple(eqs.a), tuple(wrt), mass,
                            forcing, residual.jacobian(variables))


def cycle_equations(eqs, wrt, replace=None) -> tuple:
    """Steady running of one coordinate in the crank angle: ``h = a / omega`` with
    ``a = f / I_red``, its derivative in ``omega`` and its gradient in ``wrt`` —
    ``(h, dh/domega, [dh/dp...])`` in ``q[0]``, ``u[0]`` and the parameters."""
    replace = replace or {}
    omega = eqs.u[0]
    h = (eqs.smooth_forcing[0] / eqs.mass_matrix[0, 0]).xreplace(replace) / omega
    return h, sp.diff(h, omega), [sp.diff(h, p) for p in wrt]


def stop_derivatives(expression, q, u, wrt) -> tuple:
    """A stop function ``g`` and its derivatives: ``(g, dg/d[q, u], dg/dt, dg/dp)``."""
    expression = sp.sympify(expression)
    state = list(q) + list(u)
    return (expression, [sp.diff(expression, s) for s in state], sp.diff(expression, t),
            [sp.diff(expression, p) for p in wrt])
