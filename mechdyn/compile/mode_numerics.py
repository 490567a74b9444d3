"""Compiled numerics of friction modes: the constrained equations of a mode and the
holding margins of its stuck groups, from a scene's ``terms`` vector.

Generic code, compiled once per installation (cached on disk); each scene's generated
``mode_rhs`` and ``mode_events`` (:mod:`mechdyn.compile.mode_code`) evaluate the
scene's ``terms`` and call these (through their C entry points,
:mod:`mechdyn.compile.mode_entry`) with the scene's ``layout`` (the offsets below) and
the parameter vector ``p``, which carries the mode after the scene's parameters
(:func:`mechdyn.compile.mode_code.mode_vector`). The mathematics is the one of
:mod:`mechdyn.simulate.constrained`, which stays the reference:

    M a - G_L' lambda_L - G_G' lambda_G + sum g_i l_i = f
    G_L a = -bias_L,    G_G a = -bias_G
    l_i + c lambda_L[c_i] = s_i b      (line (c, b) of a sliding lossy gear's law)
    lambda_L[c_i] = 0                  (a self-locking gear at its corner)

solved by LU with partial pivoting (:mod:`mechdyn.kernels.linalg`); each sliding gear's
line is the first (in the order of ``itertools.product``) whose solution confirms it,
else the one that misses least.
"""
import math

import numpy as np
from numba import njit

from mechdyn.numba_cache import CACHED

from mechdyn.kernels.linalg import lu_factor, lu_solve

__all__ = ["LAYOUT_NAMES", "constrained", "group_margins", "frozen_speeds", "rank_margin",
           "least_change"]

#: the entries of a scene's ``layout`` vector, then its gaps' event indices, then
#: (friction element, loop constraint) of each lossy gear
LAYOUT_NAMES = ("n", "frictions", "loops", "params", "events", "terms", "mass", "forcing",
                "friction_gradient", "friction_bias", "friction_magnitude", "friction_peak",
                "friction_release", "contact_gradient", "contact_bias",
                "constraint_gradient", "constraint_bias", "gear_law", "first_sign",
                "gaps", "gears")
(N, K, L, NP, E, T, MASS, FORCE, FG, FB, FM, FP, FREL, CG, CB, LG, LB, GL, SIGN0, GAPS,
 GEARS) = range(len(LAYOUT_NAMES))
HEAD = len(LAYOUT_NAMES)
CONTACT, GEAR, ONE_WAY = 2.0, 3.0, 1.0
_CORNER = 1e-300        # a self-locking gear's loss just past its corner


@njit(inline="always")
def _row(buf, lay, e, j):
    n, k = lay[N], lay[K]
    if e < k:
        return buf[lay[FG] + e * n + j]
    return buf[lay[CG] + (e - k) * n + j]


@njit(inline="always")
def _bias(buf, lay, e):
    if e < lay[K]:
        return buf[lay[FB] + e]
    return buf[lay[CB] + e - lay[K]]


@njit(inline="always")
def _gear(lay, i):
    at = HEAD + lay[GAPS] + 2 * i
    return lay[at], lay[at + 1]


@njit(inline="always")
def _line(buf, lay, i, line):
    """``(slope, offset, self-locking)`` of line ``line`` of gear ``i``'s law."""
    eta_f, eta_b = buf[lay[GL] + 4 * i], buf[lay[GL] + 4 * i + 1]
    locking = eta_b <= 0.0
    if line == 0 or locking:
        return 1.0 - eta_f, buf[lay[GL] + 4 * i + 2], locking
    return 1.0 - 1.0 / eta_b, buf[lay[GL] + 4 * i + 3], locking


@njit(inline="always")
def _loss(buf, lay, i, x, tolerance):
    """``L(x)`` of gear ``i`` (infinite for a self-locking gear at ``x <= tolerance``)."""
    s1, o1, locking = _line(buf, lay, i, 0)
    if locking:
        return math.inf if x <= tolerance else s1 * x + o1
    s2, o2, _ = _line(buf, lay, i, 1)
    return max(s1 * x + o1, s2 * x + o2)


@njit(cache=CACHED, error_model="numpy")
def _solve(buf, lay, p, m, sliding, count, lines, x):
    """One linear solve with the gears' ``lines``; False where it is singular."""
    n, loops, np_ = lay[N], lay[L], lay[NP]
    size = n + loops + m + count
    a = np.zeros((size, size))
    piv = np.zeros(size, np.int64)
    for i in range(n):
        for j in range(i + 1):
            a[i, j] = buf[lay[MASS] + i * (i + 1) // 2 + j]
            a[j, i] = a[i, j]
        x[i] = buf[lay[FORCE] + i]
    for r in range(loops):
        for j in range(n):
            a[n + r, j] = buf[lay[LG] + r * n + j]
            a[j, n + r] = -buf[lay[LG] + r * n + j]
        x[n + r] = -buf[lay[LB] + r]
    for g in range(m):
        e = int(p[np_ + 1 + g])
        for j in range(n):
            a[n + loops + g, j] = _row(buf, lay, e, j)
            a[j, n + loops + g] = -_row(buf, lay, e, j)
        x[n + loops + g] = -_bias(buf, lay, e)
    for s in range(count):
        k, c = _gear(lay, sliding[s])
        r, sign = n + loops + m + s, p[lay[SIGN0] + k]
        for j in range(n):
            a[j, r] = _row(buf, lay, k, j)
        slope, offset, locking = _line(buf, lay, sliding[s], lines[s])
        if locking and lines[s] == 1:          # the corner: no moment through the mesh
            a[r, n + c] = 1.0
            x[r] = 0.0
        else:
            a[r, r] = 1.0
            a[r, n + c] = slope
            x[r] = sign * offset
    if not lu_factor(a, piv):
        return False
    lu_solve(a, piv, x[:size])
    return True


@njit(cache=CACHED, error_model="numpy")
def _misfit(buf, lay, p, m, sliding, count, lines, x):
    """How far the sliding gears' lines are from the ones their mesh moments select."""
    n, loops = lay[N], lay[L]
    worst = 0.0
    for s in range(count):
        i = sliding[s]
        k, c = _gear(lay, i)
        sign = p[lay[SIGN0] + k]
        mesh = -sign * x[n + c]                         # s * tau
        slope, offset, locking = _line(buf, lay, i, lines[s])
        if locking and lines[s] == 1:
            worst = max(worst, _loss(buf, lay, i, _CORNER, 0.0)
                        - sign * x[n + loops + m + s])
        elif locking:
            worst = max(worst, -mesh)
        else:
            worst = max(worst, _loss(buf, lay, i, mesh, 0.0) - (slope * mesh + offset))
    return worst


@njit(cache=CACHED, error_model="numpy")
def constrained(buf, lay, p, x):
    """Accelerations, loop multipliers, group forces and gear losses into ``x``
    (length ``n + loops + groups + gears``) from the ``terms`` in ``buf``; False where
    the equations are singular."""
    m = int(p[lay[NP]])
    gears = lay[GEARS]
    sliding = np.zeros(max(gears, 1), np.int64)
    count = 0
    for i in range(gears):
        k, _ = _gear(lay, i)
        if p[lay[SIGN0] + k] != 0.0:
            sliding[count] = i
            count += 1
    lines = np.zeros(max(count, 1), np.int64)
    if count == 0:
        return _solve(buf, lay, p, m, sliding, 0, lines, x)
    best, kept = math.inf, x.copy()
    for option in range(2 ** count):
        for s in range(count):
            lines[s] = (option >> (count - 1 - s)) & 1
        if not _solve(buf, lay, p, m, sliding, count, lines, x):
            continue
        misfit = _misfit(buf, lay, p, m, sliding, count, lines, x)
        if misfit <= 0.0:
            return True
        if misfit < best:
            best = misfit
            kept[:] = x
    x[:] = kept
    return best < math.inf


@njit(cache=CACHED, error_model="numpy")
def frozen_speeds(lay, p, out):
    """Coordinates held by stuck elements: exactly zero speed and acceleration."""
    n = lay[N]
    frozen = lay[NP] + 1 + int(p[lay[NP]])
    for f in range(int(p[frozen])):
        i = int(p[frozen + 1 + f])
        out[i] = 0.0
        out[n + i] = 0.0


@njit(cache=CACHED, error_model="numpy")
def group_margins(buf, lay, p, x, ok, out):
    """Each stuck group's holding margin into ``out[E + g]``, the gaps' offsets taken
    off their entries; returns where the mode's numbers end in ``p``."""
    n, loops, np_, e_count = lay[N], lay[L], lay[NP], lay[E]
    m = int(p[np_])
    at = np_ + 2 + m + int(p[np_ + 1 + m])          # the groups' members
    tolerance = 0.0
    for i in range(n):
        tolerance = max(tolerance, abs(buf[lay[FORCE] + i]))
    tolerance = 1e-10 * (1.0 + tolerance)
    for g in range(m):
        count = int(p[at])
        at += 1
        low, high = 0.0, 0.0
        for _ in range(count):
            e, kind, alpha = int(p[at]), p[at + 1], p[at + 2]
            at += 3
            lo, hi = 0.0, math.inf
            if kind == GEAR:
                gear = 0
                for i in range(lay[GEARS]):
                    if _gear(lay, i)[0] == e:
                        gear = i
                tau = -x[n + _gear(lay, gear)[1]]
                lo = -_loss(buf, lay, gear, tau, tolerance)
                hi = _loss(buf, lay, gear, -tau, tolerance)
            elif kind != CONTACT:
                capacity = buf[lay[FP] + e] * max(buf[lay[FM] + e], 0.0)
                lo, hi = -capacity, capacity
                if kind == ONE_WAY:
                    lo, hi = -max(capacity, buf[lay[FREL] + e]), math.inf
            low += min(alpha * lo, alpha * hi)
            high += max(alpha * lo, alpha * hi)
        force = x[n + loops + g]
        out[e_count + g] = min(high - force, force - low) if ok else np.nan
    for j in range(lay[GAPS]):
        out[lay[HEAD + j]] -= p[at + j]
    return at + lay[GAPS]


@njit(cache=CACHED, error_model="numpy")
def rank_margin(buf, lay):
    """The smallest singular value of the loops' gradients ``G`` with every column
    scaled to unit length (:func:`mechdyn.compile.loop_numeric.rank_margin`)."""
    n, loops = lay[N], lay[L]
    part = np.empty((loops, n))
    largest = 0.0
    norms = np.zeros(n)
    for j in range(n):
        for r in range(loops):
            part[r, j] = buf[lay[LG] + r * n + j]
            norms[j] += part[r, j] ** 2
        norms[j] = math.sqrt(norms[j])
        largest = max(largest, norms[j])
    for j in range(n):
        scale = max(norms[j], 1e-12 * max(largest, 1e-300))
        for r in range(loops):
            part[r, j] /= scale
    if not np.all(np.isfinite(part)):
        return np.nan
    values = np.linalg.svd(part)[1]
    return values[loops - 1] if values.shape[0] >= loops else 0.0


@njit(cache=CACHED, error_model="numpy")
def least_change(grads, residual):
    """The smallest ``x`` with ``grads x = residual`` (``grads`` m x n of full row rank:
    ``x = G' (G G')^-1 r``, LU with partial pivoting); least squares (LAPACK) where
    ``G G'`` is singular. The projections onto closed loops take it."""
    m, n = grads.shape
    normal = grads @ grads.T
    piv = np.zeros(m, np.int64)
    y = residual.copy()
    if not lu_factor(normal, piv):
        return np.linalg.lstsq(grads, residual)[0]
    lu_solve(normal, piv, y)
    return grads.T @ y
