"""Transmission functions of closed loops, symbolically: implicit differentiation of the
loop constraints, and the reduced inertia and moment they give.

With the constraint Jacobian split into independent and dependent columns,
``G = [G_i | G_d]``, the speeds are ``u = S u_i`` with

    S = [1 ; -G_d^-1 G_i]                       (first-order transmission functions q')
    q_d'' = -G_d^-1 bias(q, q')                 (second order, for a one-DOF linkage)

and ``I_red = S' M S``, ``M_red = S' Q``; for a one-DOF linkage
``I_red'/2 = S' M q'' - S' f_in(q, q')`` (``f_in`` the velocity terms of the forcing).
The results are expressions in the coordinates' plain symbols (the crank angle ``phi``
and the dependent angles, whose values come from the position analysis); ``I_red`` is
also given in the transmission functions themselves, ``theta_2'``, as textbooks write it.

>>> import sympy as sp, mechdyn as md
>>> phi, x = md.coordinates("phi x")
>>> yoke = md.Mechanism("Scotch yoke as a loop", [phi, x])
>>> _ = yoke.link("crank", J=1, angle=phi)
>>> _ = yoke.link("yoke", m=2, x=x)
>>> _ = yoke.constraint("slot", x - sp.cos(phi))
>>> ratios(yoke.equations())[md.plain(x)]
-sin(phi)
>>> reduced_inertia(yoke.equations())
2*sin(phi)**2 + 1
"""
from __future__ import annotations

import sympy as sp

from mechdyn.errors import DerivationError
from mechdyn.symbols import t

__all__ = ["Ratio", "ratio_symbol", "velocity_matrix", "ratios", "second_ratios",
           "reduced_inertia", "reduced_inertia_in_ratios", "reduced_moment"]

_SIMPLIFY_LIMIT = 400     # operations; larger results are left as derived


class Ratio(sp.Symbol):
    """The symbol of a transmission function ``dq/dphi`` (one prime) or ``d2q/dphi2``
    (two), printed ``theta_2'`` in text and with primes on the letter in LaTeX."""

    def _latex(self, printer):
        base = self.name.rstrip("'")
        return printer._print(sp.Symbol(base)) + "'" * (len(self.name) - len(base))


def ratio_symbol(q, order=1) -> Ratio:
    """``theta_2'`` for the plain symbol ``theta_2`` (``order`` primes)."""
    return Ratio(str(q) + "'" * order)


def _split(eqs):
    if not eqs.constraints:
        raise DerivationError(f"{eqs.name!r} has no loops: transmission functions come "
                              "from loop constraints (mech.loop, mech.constraint)")
    if eqs.rheonomic or any(t in c.expression.free_symbols for c in eqs.constraints):
        raise DerivationError(f"{eqs.name!r}: positions depend explicitly on time t, so "
                              "transmission functions of the crank angle do not exist")
    independent = [eqs.q.index(q) for q in eqs.independent]
    dependent = [i for i in range(eqs.dof) if i not in independent]
    grads = sp.Matrix([[c.gradient[i] for i in range(eqs.dof)] for c in eqs.constraints])
    return grads, independent, dependent


def velocity_matrix(eqs) -> sp.Matrix:
    """``S`` (n x k): ``u = S u_i``, the speeds of all coordinates from the independent
    (kept with the equations: simplifying it is the slow part)."""
    cached = getattr(eqs, "_velocity_matrix", None)
    if cached is None:
        cached = _velocity_matrix(eqs)
        eqs._velocity_matrix = cached
    return cached


def _velocity_matrix(eqs) -> sp.Matrix:
    grads, independent, dependent = _split(eqs)
    k = len(independent)
    dependent_part = -grads[:, dependent].LUsolve(grads[:, independent])
    rows = []
    for i in range(eqs.dof):
        if i in independent:
            rows.append([1 if j == independent.index(i) else 0 for j in range(k)])
        else:
            rows.append(list(_tidy(dependent_part[dependent.index(i), :])))
    return sp.Matrix(rows)


def ratios(eqs) -> dict:
    """First-order transmission functions ``dq_j/dphi`` of a one-DOF linkage, by the
    plain symbol of each dependent coordinate."""
    matrix = velocity_matrix(eqs)
    _one_dof(eqs, "transmission functions")
    return {eqs.q[i]: matrix[i, 0] for i in range(eqs.dof) if eqs.q[i] not in eqs.independent}


def second_ratios(eqs, in_ratios=True) -> dict:
    """Second-order transmission functions ``d2q_j/dphi2`` of a one-DOF linkage, written
    in the first-order ones (``theta_2'``) when ``in_ratios``, else in the positions."""
    _one_dof(eqs, "transmission functions")
    grads, independent, dependent = _split(eqs)
    first = _first_symbols(eqs, ratios(eqs) if not in_ratios else None)
    bias = sp.Matrix([c.bias.xreplace(first) for c in eqs.constraints])
    second = -grads[:, dependent].LUsolve(bias)
    return {eqs.q[i]: _tidy(second[dependent.index(i)]) for i in dependent}


def reduced_inertia_in_ratios(eqs) -> sp.Expr:
    """``I_red = S' M S`` written in the transmission functions ``theta_2'`` (the
    textbook ``sum m (v_S/omega)^2 + J (omega_i/omega)^2``)."""
    _one_dof(eqs, "reduced_inertia")
    speeds = sp.Matrix([_first_symbols(eqs)[u] for u in eqs.u])
    return _tidy(sp.expand((speeds.T * eqs.mass_matrix * speeds)[0, 0]))


def reduced_inertia(eqs) -> sp.Expr:
    """``I_red`` of a one-DOF linkage in the positions (transmission functions
    substituted): an expression of the crank angle and the dependent coordinates."""
    return reduced_inertia_in_ratios(eqs).xreplace(
        {ratio_symbol(q): r for q, r in ratios(eqs).items()})


def reduced_moment(eqs) -> sp.Expr:
    """``M_red = S' Q`` of a one-DOF linkage: the generalized forces reduced to the
    independent coordinate (speeds written as ``phidot`` times the ratios)."""
    _one_dof(eqs, "reduced_moment")
    matrix = velocity_matrix(eqs)
    speeds = {u: matrix[i, 0] * eqs.u[eqs.q.index(eqs.independent[0])]
              for i, u in enumerate(eqs.u)}
    total = sp.Add(*[sum((matrix[i, 0] * column[i] for i in range(eqs.dof)), sp.S.Zero)
                     for column in eqs.generalized_forces.values()])
    return _tidy(total.xreplace(speeds))


def _first_symbols(eqs, values=None) -> dict:
    """Speed symbol -> its transmission function (1 for the independent coordinate)."""
    out = {}
    for q, u in zip(eqs.q, eqs.u):
        if q in eqs.independent:
            out[u] = sp.S.One
        else:
            out[u] = values[q] if values else ratio_symbol(q)
    return out


def _one_dof(eqs, what):
    if len(eqs.independent) != 1:
        raise DerivationError(f"{what}: {eqs.name!r} has {len(eqs.independent)} independent "
                              "coordinates; use velocity_matrix (S) and S' M S")


def _tidy(expr):
    """Simplified when small and free of piecewise loads (simplify is slow on those)."""
    if isinstance(expr, sp.MatrixBase):
        return expr.applyfunc(_tidy)
    if sp.count_ops(expr) > _SIMPLIFY_LIMIT or expr.has(sp.Piecewise):
        return expr
    simpler = sp.factor_terms(sp.trigsimp(sp.cancel(expr)))   # twice as fast as simplify
    return simpler if sp.count_ops(simpler) <= sp.count_ops(expr) else expr
