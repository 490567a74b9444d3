"""Numeric functions of the sensitivity equations (:mod:`mechdyn.derive.sensitivity`):
sympy's ``lambdify`` with common subexpressions shared, parameters in a vector.

:class:`ForwardSystem` evaluates the state and its sensitivities together,
``z = [y, S.ravel()]`` (``S``: 2n rows, one column per parameter differentiated for);
:class:`CycleSystem` the steady-running cycle in the crank angle; :func:`stop_function`
a stop condition with its derivatives.

>>> import sympy as sp, mechdyn as md
>>> from mechdyn.derive.sensitivity import forward_equations
>>> phi = md.coordinate("phi")
>>> J, M = sp.symbols("J M", positive=True)
>>> disc = md.Mechanism("disc", [phi])
>>> _ = disc.link("disc", J=J, angle=phi)
>>> _ = disc.load("drive", M, along=phi)
>>> system = ForwardSystem(forward_equations(disc.equations(), [J, M]), [J, M])
>>> system.rhs(0.0, [0, 0, 0, 0, 0, 0], [2.0, 6.0]).tolist()  # a = M/J, da/dJ = -M/J^2
[0.0, 3.0, 0.0, 0.0, -1.5, 0.5]
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from mechdyn.symbols import t

__all__ = ["ForwardSystem", "CycleSystem", "stop_function", "lambdified"]


def lambdified(args, exprs):
    """A function of scalars returning the list ``exprs`` (flattened: matrices entry by
    entry), by ``sp.lambdify`` over the math module with common subexpressions shared."""
    flat = [e for expr in exprs for e in (expr if isinstance(expr, sp.MatrixBase) else [expr])]
    return sp.lambdify(args, flat, modules=["math"], cse=True)


class ForwardSystem:
    """``rhs(t, z, p)`` of the state with its sensitivities; ``parameters``: the symbols
    of the vector ``p``, in order."""

    def __init__(self, forward, parameters):
        self.n, self.k = len(forward.q), len(forward.wrt)
        args = [t, *forward.q, *forward.u, *parameters]
        self._mass_force = lambdified(args, [forward.mass, forward.forcing])
        self._residual = lambdified(args + list(forward.a), [forward.residual_jacobian])

    def _solved(self, t_now, y, p):
        n = self.n
        values = self._mass_force(t_now, *y, *p)
        if n == 1:
            return values[0], np.array([values[1] / values[0]])
        mass = np.array(values[:n * n], dtype=float).reshape(n, n)
        return mass, np.linalg.solve(mass, np.array(values[n * n:], dtype=float))

    def rhs(self, t_now, z, p) -> np.ndarray:
        n, k = self.n, self.k
        z = np.asarray(z, dtype=float)
        y, s = z[:2 * n], z[2 * n:].reshape(2 * n, k)
        mass, a = self._solved(t_now, y, p)
        residual = np.array(self._residual(t_now, *y, *p, *a), dtype=float)
        residual = residual.reshape(n, 2 * n + k)
        slopes = residual / mass if n == 1 else np.linalg.solve(mass, residual)
        ds = np.empty((2 * n, k))
        ds[:n] = s[n:]
        ds[n:] = slopes[:, :2 * n] @ s + slopes[:, 2 * n:]
        return np.concatenate([y[n:], a, ds.ravel()])


class CycleSystem:
    """One cycle of steady running in the crank angle with the sensitivities the
    fixed point needs: ``z = [omega, t, v, t_v, w..., t_w...]`` — ``v = d omega/d omega0``,
    ``w = d omega/dp`` (from ``w(phi0) = 0``) and the derivatives of ``t`` alike."""

    def __init__(self, cycle_equations, coordinate, speed, parameters):
        h, h_omega, h_p = cycle_equations
        self.k = len(h_p)
        self._f = lambdified([coordinate, speed, *parameters], [h, h_omega, *h_p])

    def rhs(self, phi, z, p) -> np.ndarray:
        k = self.k
        omega, v, w = z[0], z[2], z[4:4 + k]
        h, h_omega, *h_p = self._f(phi, omega, *p)
        inverse_square = -1.0 / omega ** 2
        return np.concatenate([[h, 1.0 / omega, h_omega * v, inverse_square * v],
                               h_omega * w + np.array(h_p, dtype=float),
                               inverse_square * w])


def stop_function(derivatives, q, u, parameters):
    """``f(t, y, p) -> (g, dg/dy, dg/dt, dg/dp)`` from
    :func:`mechdyn.derive.sensitivity.stop_derivatives`."""
    g, g_y, g_t, g_p = derivatives
    function = lambdified([t, *q, *u, *parameters], [g, *g_y, g_t, *g_p])
    m = len(g_y)

    def evaluate(t_now, y, p):
        values = function(t_now, *y, *p)
        return (float(values[0]), np.array(values[1:m + 1], dtype=float),
                float(values[m + 1]), np.array(values[m + 2:], dtype=float))
    return evaluate
