"""The mean of a moment ``M(q, omega)`` over a cycle of its position ``q``, as a
vectorized function of the speed.

Where the moment switches (``Piecewise``, ``Heaviside``, ``Max``, ``Min``, ``Abs``,
``sign`` of the position) the switching positions are found once (sampled, then
refined by ``brentq``) and taken as knots; between knots the moment is smooth and is
integrated by composite Gauss-Legendre rules, so a short load pulse counts with its exact
width; a switching function of the position times one of the speed (a slider's speed
``x'(q) omega``) switches where its position factor does, and one whose zeros move with
the speed (a condition on ``q + omega / 100``) gets its knots per speed. Zeros are
sampled at ``_SAMPLES`` positions per cycle: a pulse narrower than one sample interval
(0.018 degrees of a turn) can be missed. The moment is evaluated on arrays broadcast to
one shape, so conditions of position *and* speed are evaluated elementwise.

>>> import numpy as np, sympy as sp
>>> q, u = sp.symbols("q u")
>>> pulse = sp.Piecewise((100, (q > 1) & (q < 1.01) & (u > 0)), (0, True))
>>> mean = cycle_mean(pulse, q, u, 2 * np.pi)
>>> [round(float(m), 12) for m in mean(np.array([-1.0, 5.0])) * 2 * np.pi]   # 100 * 0.01
[0.0, 1.0]
"""
from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.optimize import brentq

from mechdyn.compile.generate import Switches

__all__ = ["cycle_mean"]

_SAMPLES = 20000         # positions a switching function is sampled at for its zeros
_PANEL = 2 * np.pi / 16   # the widest panel of the Gauss-Legendre rule
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(16)


def cycle_mean(expr, q, u, cycle):
    """``lambda w: mean over q in [0, cycle) of expr(q, w)`` (see the module)."""
    switches = Switches({q, u})
    switches.lock(expr)
    positions, moving = [], []
    for g in (g for g in switches.functions if g.has(q)):
        parts = sp.separatevars(g, symbols=[q, u], dict=True) if g.has(u) else {q: g}
        if parts is None:
            moving.append(sp.lambdify((q, u), g, "numpy"))
        else:                         # g = h(q) k(u): its zeros in q are those of h
            positions.append(sp.lambdify(q, parts[q], "numpy"))
    grid = np.linspace(0.0, cycle, _SAMPLES + 1)
    fixed = [0.0, cycle] + [x for h in positions for x in _zeros(h, grid, h(grid))]
    if not moving:                    # the terms without the speed: their mean once
        nodes, weights = _rule(np.unique(fixed))
        still, moved = expr.as_independent(u, as_Add=True)
        base = _values(sp.lambdify((q, u), still, "numpy"), nodes, 0.0)[:, 0] @ weights
        g = sp.lambdify((q, u), moved, "numpy")
        return lambda w: (base + _values(g, nodes, w).T @ weights) / cycle
    f = sp.lambdify((q, u), expr, "numpy")

    def mean(w):                      # knots that move with the speed: per speed
        speeds = np.atleast_1d(np.asarray(w, dtype=float))
        out = np.empty(len(speeds))
        for i, speed in enumerate(speeds):
            knots = fixed + [x for g in moving
                             for x in _zeros(lambda x, g=g: g(x, speed), grid,
                                             _values(g, grid, speeds[i:i + 1])[:, 0])]
            nodes, weights = _rule(np.unique(knots))
            out[i] = _values(f, nodes, speeds[i:i + 1])[:, 0] @ weights / cycle
        return out.reshape(np.shape(w))
    return mean


def _values(f, angles, w):
    """``f`` at every (angle, speed): an array (angles x speeds), built elementwise."""
    angles, speeds = np.broadcast_arrays(np.asarray(angles, dtype=float)[:, None],
                                         np.atleast_1d(np.asarray(w, dtype=float))[None, :])
    return np.broadcast_to(np.asarray(f(angles.copy(), speeds.copy()), dtype=float),
                           angles.shape)


def _zeros(g, grid, values) -> list:
    """Where ``g(q)`` (``values`` on ``grid``) changes sign inside the grid."""
    signs = np.sign(np.broadcast_to(np.asarray(values, dtype=float), grid.shape))
    zeros = [float(grid[i]) for i in np.flatnonzero(signs == 0)]
    for i in np.flatnonzero(signs[:-1] * signs[1:] < 0):
        zeros.append(brentq(lambda x: float(g(x)), grid[i], grid[i + 1], xtol=1e-15,
                            rtol=4 * np.finfo(float).eps))
    return zeros


def _rule(knots):
    """Nodes and weights of composite 16-point Gauss-Legendre rules between the knots
    (panels no wider than ``_PANEL``)."""
    nodes, weights = [], []
    for a, b in zip(knots[:-1], knots[1:]):
        panels = max(1, int(np.ceil((b - a) / _PANEL)))
        edges = np.linspace(a, b, panels + 1)
        for lo, hi in zip(edges[:-1], edges[1:]):
            half = (hi - lo) / 2
            nodes.append(lo + half * (_NODES + 1))
            weights.append(half * _WEIGHTS)
    return np.concatenate(nodes), np.concatenate(weights)
