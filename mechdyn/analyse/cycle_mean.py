"""The mean of a moment ``M(q, omega)`` over a cycle of its position ``q``, as a
vectorized function of the speed.

Where the moment switches (``Piecewise``, ``Heaviside``, ``Max``, ``Min``, ``Abs``,
``sign`` of the position) the switching positions are found once (sampled, then
refined by ``brentq``) and taken as knots; between knots the moment is smooth and is
integrated by composite Gauss-Legendre rules, so a short load pulse counts with its exact
width; a switching function of the position times one of the speed (a slider's speed
``x'(q) omega``) switches where its position factor does. A switch whose position moves
with the speed (a condition on ``q + omega``) has no fixed knots: the mean then comes from a fine midpoint rule whose error is estimated
by halving it, and a :class:`~mechdyn.errors.MechdynWarning` states the estimate where
it exceeds 0.1 %. The moment is evaluated on arrays broadcast to one shape, so
conditions of position *and* speed are evaluated elementwise.

>>> import numpy as np, sympy as sp
>>> q, u = sp.symbols("q u")
>>> pulse = sp.Piecewise((100, (q > 1) & (q < 1.01) & (u > 0)), (0, True))
>>> mean = cycle_mean(pulse, q, u, 2 * np.pi, "a pulse")
>>> [round(float(m), 12) for m in mean(np.array([-1.0, 5.0])) * 2 * np.pi]   # 100 * 0.01
[0.0, 1.0]
"""
from __future__ import annotations

import warnings

import numpy as np
import sympy as sp
from scipy.optimize import brentq

from mechdyn.compile.generate import Switches
from mechdyn.errors import MechdynWarning

__all__ = ["cycle_mean", "TOLERANCE"]

TOLERANCE = 1e-3          # a sampled mean whose estimated error exceeds this warns
_SAMPLES = 20000          # positions a switching function is sampled at for its zeros
_PANEL = 2 * np.pi / 64   # the widest panel of the Gauss-Legendre rule
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(16)
_MIDPOINTS = 8192         # a sampled mean's points per cycle


def cycle_mean(expr, q, u, cycle, what):
    """``lambda w: mean over q in [0, cycle) of expr(q, w)`` (see the module)."""
    f = sp.lambdify((q, u), expr, "numpy")
    switches = Switches({q, u})
    switches.lock(expr)
    positions, moving = [], []
    for g in (g for g in switches.functions if g.has(q)):
        parts = sp.separatevars(g, symbols=[q, u], dict=True) if g.has(u) else {q: g}
        if parts is None:
            moving.append(g)
        else:                         # g = h(q) k(u): its zeros in q are those of h
            positions.append(parts[q])
    if moving:
        return _sampled(f, cycle, what, moving)
    fixed = [sp.lambdify(q, h, "numpy") for h in positions]
    knots = np.unique(np.concatenate([[0.0, cycle]] + [_zeros(g, cycle) for g in fixed]))
    nodes, weights = _rule(knots)
    return lambda w: _values(f, nodes, w).T @ weights / cycle


def _values(f, angles, w):
    """``f`` at every (angle, speed): an array (angles x speeds), built elementwise."""
    angles, speeds = np.broadcast_arrays(np.asarray(angles, dtype=float)[:, None],
                                         np.atleast_1d(np.asarray(w, dtype=float))[None, :])
    return np.broadcast_to(np.asarray(f(angles.copy(), speeds.copy()), dtype=float),
                           angles.shape)


def _zeros(g, cycle) -> np.ndarray:
    """Where the switching function ``g(q)`` changes sign in ``(0, cycle)``."""
    grid = np.linspace(0.0, cycle, _SAMPLES + 1)
    values = np.broadcast_to(np.asarray(g(grid), dtype=float), grid.shape)
    signs = np.sign(values)
    zeros = [grid[i] for i in np.flatnonzero(signs == 0)]
    for i in np.flatnonzero(signs[:-1] * signs[1:] < 0):
        zeros.append(brentq(lambda x: float(g(x)), grid[i], grid[i + 1], xtol=1e-15,
                            rtol=4 * np.finfo(float).eps))
    return np.array(zeros, dtype=float)


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


def _sampled(f, cycle, what, moving):
    """The midpoint mean with ``_MIDPOINTS`` points; the difference to the rule of half
    as many points estimates its error, stated in a warning once past ``TOLERANCE``."""
    fine = (np.arange(_MIDPOINTS) + 0.5) * cycle / _MIDPOINTS
    coarse = (np.arange(_MIDPOINTS // 2) + 0.5) * cycle / (_MIDPOINTS // 2)
    warned = []

    def mean(w):
        values = _values(f, fine, w).mean(axis=0)
        error = np.abs(values - _values(f, coarse, w).mean(axis=0))
        scale = np.maximum(np.abs(values), np.max(np.abs(values), initial=0.0) * 1e-3)
        worst = float(np.max(np.divide(error, scale, out=np.zeros_like(error),
                                       where=scale > 0), initial=0.0))
        if worst > TOLERANCE and not warned:
            warned.append(worst)
            warnings.warn(
                f"{what}: its switching points move with the speed "
                f"({', '.join(map(str, moving))} = 0), so its mean over a cycle is "
                f"sampled at {_MIDPOINTS} positions, with an estimated error up to "
                f"{100 * worst:.2g} % (a condition on the position alone is averaged "
                "exactly)", MechdynWarning, stacklevel=4)
        return values
    return mean
