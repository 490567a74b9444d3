"""A sparse LU of the iteration matrix where no narrow band exists: trees and meshes.

A tree of discs has no narrow band in any numbering (its widest level sets the band),
but eliminated leaves first it factors without a single fill-in. :func:`symbolic` finds
such an order, the minimum-degree ordering of the graph of the matrix's non-zeros
(each step eliminates a state of fewest remaining neighbours and joins those
neighbours: the fill), and records each state's neighbours at its elimination: the
structure of its row of ``U`` and column of ``L``. It gives up (the caller factors
dense) where the fill outgrows :func:`capacity` or the sparse work would not be a
quarter of the dense ``n^3 / 3``.

:func:`factor` then eliminates in that order without row interchanges, so the
structure holds, after checking each pivot against its column (the threshold test of
sparse direct solvers, ``|pivot| >= THRESHOLD * max |column|``): a pivot that fails it
stops the factorisation, and the caller factors dense with partial pivoting instead.
The iteration matrix ``c I - J`` of a mechanism is diagonally dominant for small steps
and ``M^-1`` times a symmetric positive definite matrix for large ones (its stiffness
and damping are), so the test passes on the machines mechdyn models.

The structure lives in ``plan_`` after its first three entries: ``size + 1`` row
starts, then the column places of the rows (places, not states: ``order[k]`` is the
state at place ``k``). A star of 6 states (state 0 joined to all others), which a band
would factor whole, eliminated leaves first:

>>> import numpy as np
>>> a = np.eye(6) * 10.0; a[0, 1:] = a[1:, 0] = 1.0
>>> plan_ = np.zeros(3 + 7 + capacity(6), np.int64)
>>> order, position, degree = (np.zeros(6, np.int64) for _ in range(3))
>>> symbolic(a, plan_, order, position, degree, np.zeros((6, 6)))    # work: 5 rows of 1
5
>>> order.tolist(), int(plan_[3 + 6] - plan_[3])   # leaves first; U: the 5 edges, no fill
([1, 2, 3, 4, 0, 5], 5)
>>> W = np.zeros((6, 6)); factor(-a, 0.0, plan_, order, W)   # 0 I - (-a) = a
True
>>> b = a @ np.arange(6.0); solve(plan_, order, W, b, np.zeros(6))
>>> bool(np.allclose(b, np.arange(6.0), rtol=0, atol=1e-14))
True
"""
from numba import njit

__all__ = ["SPARSE", "THRESHOLD", "capacity", "factor", "solve", "symbolic"]

SPARSE = -2          #: ``plan_[1]`` of a matrix factored by this module
THRESHOLD = 0.01     #: a pivot at least this fraction of its column's largest entry
_STARTS = 3          #: where the row starts begin in ``plan_``


@njit(inline="always")
def capacity(n):
    """Entries of ``U`` (above the diagonal) the structure of an ``n x n`` matrix may
    hold: eight a row, a tree's one, a planar mesh's few (nested fill included)."""
    return 8 * n


@njit
def symbolic(pattern, plan_, order, position, degree, graph):
    """Minimum-degree order and filled structure of ``pattern``'s non-zeros (``pattern[i,
    j]`` or ``pattern[j, i]``) into ``order``, ``position`` and ``plan_``; ``graph`` is
    work space of the same size. Returns the factorisation's work (the sum of the
    squared row lengths of ``U``), or -1 where it does not fit or does not pay."""
    n = pattern.shape[0]
    for i in range(n):
        count = 0
        for j in range(n):
            linked = i != j and (pattern[i, j] != 0.0 or pattern[j, i] != 0.0)
            graph[i, j] = 1.0 if linked else 0.0
            count += linked
        degree[i] = count
        position[i] = -1
    entries = _STARTS + n + 1
    limit = entries + capacity(n)
    if plan_.shape[0] < limit:
        return -1
    plan_[_STARTS] = entries
    work = 0
    for k in range(n):
        state = -1
        for i in range(n):                 # fewest remaining neighbours; ties: first
            if position[i] < 0 and (state < 0 or degree[i] < degree[state]):
                state = i
        order[k], position[state] = state, k
        first = plan_[_STARTS + k]
        last = first
        for j in range(n):
            if graph[state, j] != 0.0:
                if last >= limit:
                    return -1
                plan_[last] = j
                last += 1
        plan_[_STARTS + k + 1] = last
        work += (last - first) * (last - first)
        for a in range(first, last):       # the neighbours become a clique: the fill
            u = plan_[a]
            graph[u, state] = graph[state, u] = 0.0
            degree[u] -= 1
            for b in range(a + 1, last):
                v = plan_[b]
                if graph[u, v] == 0.0:
                    graph[u, v] = graph[v, u] = 1.0
                    degree[u] += 1
                    degree[v] += 1
    if 12 * work > n * n * n:              # not a quarter of the dense work
        return -1
    for e in range(entries, plan_[_STARTS + n]):
        plan_[e] = position[plan_[e]]
    return work


@njit(inline="always")
def factor(matrix, diagonal, plan_, order, W):
    """``W`` := the LU factors of ``diagonal I - matrix`` renumbered by ``order``, at the
    places of :func:`symbolic`'s structure only. False at a pivot that fails the
    threshold test, is zero or is not finite."""
    n = matrix.shape[0]
    for k in range(n):
        s = order[k]
        W[k, k] = diagonal - matrix[s, s]
        for e in range(plan_[_STARTS + k], plan_[_STARTS + k + 1]):
            j = plan_[e]
            t = order[j]
            W[k, j] = -matrix[s, t]
            W[j, k] = -matrix[t, s]
    for k in range(n):
        first, last = plan_[_STARTS + k], plan_[_STARTS + k + 1]
        pivot = W[k, k]
        largest = abs(pivot)
        for e in range(first, last):
            largest = max(largest, abs(W[plan_[e], k]))
        if not (abs(pivot) >= THRESHOLD * largest and 0.0 < abs(pivot) < 1e308):
            return False
        for e in range(first, last):
            i = plan_[e]
            multiplier = W[i, k] / pivot
            W[i, k] = multiplier
            if multiplier != 0.0:
                for f in range(first, last):
                    j = plan_[f]
                    W[i, j] -= multiplier * W[k, j]
    return True


@njit(inline="always")
def solve(plan_, order, W, b, work):
    """Solve in place in ``b`` from :func:`factor`'s factors; ``work`` as long as ``b``."""
    n = b.shape[0]
    for k in range(n):
        work[k] = b[order[k]]
    for k in range(n):                     # L (unit diagonal), column by column
        value = work[k]
        if value != 0.0:
            for e in range(plan_[_STARTS + k], plan_[_STARTS + k + 1]):
                work[plan_[e]] -= W[plan_[e], k] * value
    for k in range(n - 1, -1, -1):         # U, row by row
        total = work[k]
        for e in range(plan_[_STARTS + k], plan_[_STARTS + k + 1]):
            total -= W[k, plan_[e]] * work[plan_[e]]
        work[k] = total / W[k, k]
    for k in range(n):
        b[order[k]] = work[k]
