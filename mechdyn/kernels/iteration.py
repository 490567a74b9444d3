"""The iteration matrix ``c I - J`` of a Rosenbrock step (``c = 1 / (h gamma)``): how it
is factored and solved, chosen on every Jacobian by :func:`plan` and carried out by
:func:`factor` and :func:`solve`.

Small models (below 16 states) keep the dense LU of the whole matrix. Larger ones:

- **Second-order structure** (every model of a mechanism: ``J = [[0, I], [A, B]]``, the
  positions' derivatives are the speeds; checked entry by entry on each Jacobian): the
  positions are eliminated, as Hairer's RODAS and RADAU5 do for ``M1 > 0``. Of
  ``c k1 - k2 = r1``, ``-A k1 + (c I - B) k2 = r2`` there remains
  ``(c I - B - A / c) k2 = r2 + A r1 / c``, then ``k1 = (r1 + k2) / c``: a matrix of
  half the size, an eighth of the dense work.
- **A band**: the matrix that is factored (the whole ``c I - J`` or
  the reduced one) is renumbered by :func:`mechdyn.kernels.band.order_states` and factored
  as a band where that is much cheaper (:func:`mechdyn.kernels.band.is_narrow`); the band
  is measured on each Jacobian, so no non-zero lies outside it.
- **Sparse** where no narrow band exists (a tree, a mesh) and a minimum-degree
  elimination keeps the fill small (:mod:`mechdyn.kernels.sparse`: no row
  interchanges, each pivot checked against its column; one that fails the check
  turns this factorisation dense).
- Otherwise dense LU with partial pivoting (:mod:`mechdyn.kernels.linalg`).

``plan_`` (:func:`plan_size` entries) holds ``[reduced, kl, ku]`` (kl = -1: dense,
:data:`~mechdyn.kernels.sparse.SPARSE`: sparse, its structure following); ``order`` /
``position`` the renumbering of the factored matrix's states.

A chain of 8 unit discs on unit springs (16 states: reduced to 8, a band of width 1):

>>> import numpy as np
>>> n, m = 16, 8
>>> J = np.zeros((n, n)); J[range(m), range(m, n)] = 1.0
>>> J[m:, :m] = np.eye(m, k=1) + np.eye(m, k=-1) - np.diag([1.0] + [2.0] * 6 + [1.0])
>>> plan_, order, position = (np.zeros(plan_size(n), np.int64), np.zeros(n, np.int64),
...                           np.zeros(n, np.int64))
>>> W = np.zeros((n, n))
>>> plan(J, plan_, order, position, np.zeros(n, np.int64), np.zeros((m, m)), W, False)
True
>>> plan_[:3].tolist()                 # reduced, tridiagonal
[1, 1, 1]
>>> core, piv = np.zeros((m, m)), np.zeros(n, np.int64)
>>> factor(J, 2.0, plan_, order, W, core, piv)
True
>>> b = (2.0 * np.eye(n) - J) @ np.ones(n)
>>> solve(J, 2.0, plan_, order, position, W, piv, b, np.zeros(n)); bool(np.allclose(b, 1.0))
True
"""
from numba import njit

from .band import (BAND_MIN, band_lu_factor, band_lu_solve, bandwidths, fill_band, is_narrow,
                   is_second_order, order_states)
from .linalg import lu_factor, lu_solve
from . import sparse

__all__ = ["factor", "matvec", "plan", "plan_size", "solve"]


@njit(inline="always")
def plan_size(n):
    """Entries of the ``plan_`` of an ``n``-state Jacobian (a sparse structure's too)."""
    return 3 + n + 1 + sparse.capacity(n)


@njit(inline="always")
def plan(J, plan_, order, position, degree, core, W, ordered):
    """Choose how ``c I - J`` is factored (module doc) into ``plan_``, renumbering its
    states unless ``ordered`` (a renumbering of the same kind kept from an earlier
    Jacobian); ``core`` is work space of half J's size, ``W`` of its size. Returns
    whether a renumbering is now held."""
    n = J.shape[0]
    plan_[1] = plan_[2] = -1
    if n < BAND_MIN:                       # small: dense LU of the whole matrix
        plan_[0] = 0
        return False
    reduced = is_second_order(J)
    changed = reduced != (plan_[0] == 1)
    plan_[0] = 1 if reduced else 0
    pattern = J
    if reduced:                            # the pattern of B + A / c: A's and B's
        m = n // 2
        for i in range(m):
            for j in range(m):
                core[i, j] = abs(J[m + i, j]) + abs(J[m + i, m + j])
        pattern = core
    size = n // 2 if reduced else n
    if changed or not ordered:
        order_states(pattern[:size, :size], order[:size], position[:size], degree[:size])
    kl, ku = bandwidths(pattern[:size, :size], position[:size])
    narrow = is_narrow(size, kl, ku)
    band_work = size * (kl + 1) * (2 * kl + ku + 1)
    if narrow and band_work <= 16 * size:  # a chain's few diagonals: nothing does better
        plan_[1], plan_[2] = kl, ku
        return True
    sparse_work = sparse.symbolic(pattern[:size, :size], plan_, order[:size],
                                  position[:size], degree[:size], W[:size, :size])
    if sparse_work >= 0 and not (narrow and band_work <= 2 * sparse_work):
        plan_[1] = sparse.SPARSE
        return True
    if narrow:                  # the band, in a renumbering made afresh
        order_states(pattern[:size, :size], order[:size], position[:size], degree[:size])
        plan_[1], plan_[2] = bandwidths(pattern[:size, :size], position[:size])
        return True
    return False                # dense; the renumbering was spent: make it afresh next time


@njit(inline="always")
def factor(J, c, plan_, order, W, core, pivots):
    """Factor ``c I - J`` (or its reduced form ``c I - core``, ``core`` filled here with
    ``B + A / c``) as ``plan_`` says, into ``W``; False where a pivot is zero or not
    finite."""
    n = J.shape[0]
    reduced, kl, ku = plan_[0] == 1, plan_[1], plan_[2]
    matrix = J
    size = n
    if reduced:
        size = n // 2
        for i in range(size):
            for j in range(size):
                core[i, j] = J[size + i, size + j] + J[size + i, j] / c
        matrix = core
    if kl >= 0:
        ab = W[:size, :2 * kl + ku + 1]
        fill_band(matrix[:size, :size], order, c, ab, kl, ku)
        return band_lu_factor(ab, kl, ku, pivots)
    if kl == sparse.SPARSE:
        if sparse.factor(matrix[:size, :size], c, plan_, order, W):
            return True
        plan_[1] = -1            # a pivot the sparse order cannot take: dense, pivoting
    for i in range(size):
        for j in range(size):
            W[i, j] = -matrix[i, j]
        W[i, i] += c
    return lu_factor(W[:size, :size], pivots)


@njit(inline="always")
def _core_solve(plan_, order, W, pivots, x, work):
    size = x.shape[0]
    kl, ku = plan_[1], plan_[2]
    if kl == sparse.SPARSE:
        sparse.solve(plan_, order, W, x, work)
    elif kl >= 0:
        for i in range(size):
            work[i] = x[order[i]]
        band_lu_solve(W[:size, :2 * kl + ku + 1], kl, ku, pivots, work[:size])
        for i in range(size):
            x[order[i]] = work[i]
    else:
        lu_solve(W[:size, :size], pivots, x)


@njit(inline="always")
def solve(J, c, plan_, order, position, W, pivots, b, work):
    """Solve ``(c I - J) x = b`` in place in ``b`` from :func:`factor`'s factors;
    ``work`` has as many entries as ``b``."""
    n = b.shape[0]
    if plan_[0] != 1:
        _core_solve(plan_, order, W, pivots, b, work)
        return
    m = n // 2
    kl, ku = plan_[1], plan_[2]
    for i in range(m):                      # r2 + A r1 / c, A's non-zeros in the band
        total = 0.0
        if kl >= 0:
            place = position[i]
            for k in range(max(0, place - kl), min(m, place + ku + 1)):
                total += J[m + i, order[k]] * b[order[k]]
        else:
            for j in range(m):
                total += J[m + i, j] * b[j]
        work[i] = b[m + i] + total / c
    _core_solve(plan_, order, W, pivots, work[:m], work[m:])
    for i in range(m):
        b[m + i] = work[i]
        b[i] = (b[i] + work[i]) / c


@njit(inline="always")
def matvec(J, x, out, plan_, order, position):
    """``out = J x``, using the structure ``plan_`` found (J's non-zeros, or A's and
    B's, within the band of ``order``)."""
    n = x.shape[0]
    reduced, kl, ku = plan_[0] == 1, plan_[1], plan_[2]
    m = n // 2 if reduced else n
    if reduced:
        for i in range(m):
            out[i] = x[m + i]
    for i in range(m):
        row = m + i if reduced else i
        total = 0.0
        if kl >= 0:
            place = position[i]
            for k in range(max(0, place - kl), min(m, place + ku + 1)):
                j = order[k]
                total += J[row, j] * x[j]
                if reduced:
                    total += J[row, m + j] * x[m + j]
        else:
            for j in range(n):
                total += J[row, j] * x[j]
        out[row] = total
