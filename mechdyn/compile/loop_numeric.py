"""The numerics of closed loops that run without sympy: the error of a singular loop,
and the Python helpers generated code calls beyond the unrolled sizes (the constrained
solve, a central-difference Jacobian, the constraint minors).

>>> out = [0.0, 0.0, 0.0]
>>> numeric_minors([1.0, 2.0, 0.0, 0.0, 3.0, 4.0], 2, 3, out)   # columns (0,1) (0,2) (1,2)
>>> [round(v, 12) for v in out]
[3.0, 4.0, 8.0]
"""
from __future__ import annotations

import itertools

import numpy as np

from mechdyn.errors import SimulationError

__all__ = ["LoopSingularError", "LOOP_MARGIN", "PIVOT_FLOOR", "loop_solve",
           "numeric_jacobian", "numeric_minors", "rank_margin"]

# Smallest pivot of S, relative to its diagonal, the generated rhs accepts (below it the
# loops have lost rank numerically). Where a watched minor changes sign the driver calls
# the loops singular if every minor is below LOOP_MARGIN times its size at the start.
PIVOT_FLOOR = 1e-14
LOOP_MARGIN = 1e-6


class LoopSingularError(SimulationError):
    """The loop constraints lost rank (a change point or a locked toggle): the motion of
    the linkage is not determined there. ``loop``: the constraint that became dependent
    on the others; ``time``, ``state`` where the run stopped; after the run,
    ``kept_until``: the time ``partial`` ends (its last well-conditioned step).

    Examples
    --------
    A parallelogram four-bar (crank 1, coupler 3, rocker 1, ground 3) turning at 1 rad/s
    from ``phi = 1`` reaches its change point, all links in line, at ``phi = pi``:

    >>> import mechdyn as md
    >>> phi, th2, th3 = md.coordinates("phi theta_2 theta_3")
    >>> four = md.Mechanism("parallelogram", [phi, th2, th3])
    >>> _ = four.link("crank", J=1, angle=phi)
    >>> _ = four.link("coupler", J=1, angle=th2)
    >>> _ = four.link("rocker", J=1, angle=th3)
    >>> _ = four.loop("ABCD", (1, phi), (3, th2), (-1, th3), (-3, 0))
    >>> turning = md.Scene("turning", initial={phi: 1, th2: 0, th3: 1, md.speed(phi): 1},
    ...                    t_end=5, backend="scipy")
    >>> try:
    ...     four.simulate(turning)
    ... except md.LoopSingularError as error:
    ...     print(error.loop, round(error.time, 5), error.partial.t_end < error.time)
    ABCD 2.14159 True
    """

    def __init__(self, loop, t_value, state, detail=""):
        self.loop, self.time, self.state = loop, t_value, list(state)
        super().__init__(f"loop {loop} is singular at t = {t_value:.6g} s{detail}: its "
                         "constraints lose rank there (a change point or toggle position "
                         "where the linkage can move more than one way)")


def rank_margin(grads, columns=None):
    """The smallest of the ``m`` singular values of the constraint Jacobian ``G`` (or of
    its ``columns``) with every column scaled to unit length: 0 where the constraints
    lose rank, about 1 far from it; the same however a loop is turned or scaled (the
    column of a revolute term has the link's length as its norm).

    >>> float(rank_margin(np.array([[0.0, 0.0, 0.0], [0.1, 0.3, -0.1]])))  # all in line
    0.0
    >>> round(rank_margin(np.array([[0.0, -0.3], [0.1, 0.0]])), 12)
    1.0
    """
    part = np.asarray(grads, dtype=float)
    if columns is not None:
        part = part[:, columns]
    norms = np.linalg.norm(part, axis=0)
    part = part / np.maximum(norms, 1e-12 * max(float(norms.max(initial=0.0)), 1e-300))
    values = np.linalg.svd(part, compute_uv=False)
    return float(values[part.shape[0] - 1]) if len(values) >= part.shape[0] else 0.0


def numeric_minors(flat, m, n, out):
    """Every m x m minor of the m x n matrix ``flat``, into ``out``."""
    matrix = np.reshape(flat, (m, n))
    for k, columns in enumerate(itertools.combinations(range(n), m)):
        out[k] = float(np.linalg.det(matrix[:, list(columns)]))


def loop_solve(flat, n, m, out, offset, which):
    """``a`` (``which`` 0) or ``lambda`` (1) from the flattened ``M``, ``f``, ``G``,
    ``bias`` (numpy), into ``out[offset:]``; NaN where the loops lose rank."""
    flat = np.asarray(flat, dtype=float)
    mass = flat[:n * n].reshape(n, n)
    forcing = flat[n * n:n * n + n]
    grads = flat[n * n + n:n * n + n + m * n].reshape(m, n)
    bias = flat[n * n + n + m * n:]
    w = np.trace(mass) / np.sum(grads * grads)
    augmented = mass + w * grads.T @ grads
    try:
        z = np.linalg.solve(augmented, forcing)
        y_cols = np.linalg.solve(augmented, grads.T)
        schur = grads @ y_cols
        factor = np.linalg.cholesky(schur)
        ratios = np.diag(factor) ** 2 / np.diag(schur)
        if not np.min(ratios) > PIVOT_FLOOR:
            raise np.linalg.LinAlgError
        nu = np.linalg.solve(schur, -bias - grads @ z)
        result = z + y_cols @ nu if which == 0 else nu + w * bias
    except np.linalg.LinAlgError:
        result = np.full(n if which == 0 else m, np.nan)
    for i, value in enumerate(result):
        out[offset + i] = float(value)


def numeric_jacobian(rhs, t_value, y, p, out):
    """Central differences of a generated ``rhs(t, y, p, out)`` into ``out``
    (constrained systems have no analytic Jacobian)."""
    y = np.asarray(y, dtype=float)
    size = len(y)
    up_values, down_values = [0.0] * size, [0.0] * size
    for j in range(size):
        h = 1e-7 * max(1.0, abs(y[j]))
        up, down = y.copy(), y.copy()
        up[j] += h
        down[j] -= h
        rhs(t_value, up.tolist(), p, up_values)
        rhs(t_value, down.tolist(), p, down_values)
        out[:, j] = (np.asarray(up_values) - np.asarray(down_values)) / (2 * h)
