"""A large Jacobian's structure for the stiff step: a bandwidth-reducing ordering of the
states and an LU decomposition with partial pivoting that keeps to the band.

A machine's Jacobian is sparse: a chain of N discs couples each disc to its neighbours
only. In the order ``[q1..qN, u1..uN]`` its non-zeros still lie N places off the
diagonal, so a dense LU of Rodas5P's iteration matrix costs ``(2N)^3 / 3`` operations a
step. Renumbered by the reverse Cuthill-McKee ordering (:func:`order_states`: a
breadth-first walk of the graph of non-zeros from a node of least degree, each node's
neighbours by increasing degree, then reversed), the non-zeros of the chain lie within
three places of the diagonal, and so do those of a tree or a mesh numbered in any order
up to the width of their widest level. :func:`band_lu_factor` then costs ``n kl (kl + ku)``
(LAPACK's ``dgbtf2``, with its storage: row interchanges widen the upper band to
``kl + ku``).

The band is measured on every Jacobian (:func:`bandwidths`), not assumed from an
earlier one, so no non-zero ever lies outside it: the banded factors are those of the
whole matrix, with the pivots dense partial pivoting would choose for the renumbered
matrix. (Not :mod:`mechdyn.compile.band_linalg`'s Cholesky: ``c I - J`` is neither
symmetric nor positive definite.)

>>> import numpy as np
>>> a = np.array([[4.0, 0.0, 1.0], [0.0, 3.0, 0.0], [2.0, 0.0, 5.0]])
>>> order, position = np.zeros(3, np.int64), np.zeros(3, np.int64)
>>> order_states(a, order, position, np.zeros(3, np.int64)); order.tolist()
[2, 0, 1]
>>> kl, ku = bandwidths(a, position); (kl, ku)
(1, 1)
>>> ab, piv = np.zeros((3, 2 * kl + ku + 1)), np.zeros(3, np.int64)
>>> fill_band(a, order, 10.0, ab, kl, ku); band_lu_factor(ab, kl, ku, piv)   # 10 I - a
True
>>> b = np.array([5.0, 7.0, 3.0])[order]; band_lu_solve(ab, kl, ku, piv, b); b[position].tolist()
[1.0, 1.0, 1.0]
"""
from numba import njit

__all__ = ["BAND_MIN", "band_lu_factor", "band_lu_solve", "bandwidths", "fill_band",
           "is_narrow", "is_second_order", "order_states"]

BAND_MIN = 16        #: states from which a Jacobian is renumbered and its band measured


@njit
def order_states(J, order, position, degree):
    """Reverse Cuthill-McKee ordering of the graph of ``J``'s off-diagonal non-zeros
    (``J[i, j]`` or ``J[j, i]``): ``order[k]`` is the state at place ``k``,
    ``position[i]`` the place of state ``i``; ``degree`` is work space."""
    n = J.shape[0]
    for i in range(n):
        count = 0
        for j in range(n):
            if j != i and (J[i, j] != 0.0 or J[j, i] != 0.0):
                count += 1
        degree[i] = count
        position[i] = -1
    placed = 0
    while placed < n:
        start = -1
        for i in range(n):            # a component's walk starts at a least connected state
            if position[i] < 0 and (start < 0 or degree[i] < degree[start]):
                start = i
        order[placed] = start
        position[start] = placed
        placed += 1
        head = placed - 1
        while head < placed:
            node = order[head]
            head += 1
            first = placed
            for j in range(n):
                if position[j] < 0 and (J[node, j] != 0.0 or J[j, node] != 0.0):
                    order[placed] = j
                    position[j] = placed
                    placed += 1
            for k in range(first + 1, placed):        # the new ones by increasing degree
                state = order[k]
                m = k
                while m > first and degree[order[m - 1]] > degree[state]:
                    order[m] = order[m - 1]
                    m -= 1
                order[m] = state
            for k in range(first, placed):
                position[order[k]] = k
    for k in range(n // 2):                            # reversed: Cuthill-McKee's rule
        order[k], order[n - 1 - k] = order[n - 1 - k], order[k]
    for k in range(n):
        position[order[k]] = k


@njit
def bandwidths(J, position):
    """(kl, ku): how far below and above the diagonal the non-zeros of ``J`` lie once
    renumbered by ``position`` (NaN counts as non-zero)."""
    n = J.shape[0]
    kl = ku = 0
    for i in range(n):
        row = position[i]
        for j in range(n):
            if J[i, j] != 0.0:
                offset = position[j] - row
                if offset > ku:
                    ku = offset
                elif -offset > kl:
                    kl = -offset
    return kl, ku


@njit(inline="always")
def is_narrow(n, kl, ku):
    """Whether the banded factorisation beats the dense one by a wide margin (work
    ``n kl (kl + ku)`` against ``n^3 / 3``, memory passes counted)."""
    return 4 * (kl + 1) * (2 * kl + ku + 1) < n * n


@njit(inline="always")
def fill_band(J, order, diagonal, ab, kl, ku):
    """``ab`` := the band of ``diagonal I - J`` renumbered by ``order``, in LAPACK's
    storage: ``ab[i, kl + j - i]`` holds element ``(i, j)`` for ``-kl <= j - i <= kl +
    ku`` (the upper ``kl`` diagonals beyond ``ku`` start at zero: the pivoting's fill)."""
    n = J.shape[0]
    width = 2 * kl + ku + 1
    for i in range(n):
        source = order[i]
        for d in range(width):
            j = i + d - kl
            ab[i, d] = -J[source, order[j]] if 0 <= j < n and d <= kl + ku else 0.0
        ab[i, kl] += diagonal


@njit(inline="always")
def band_lu_factor(ab, kl, ku, piv):
    """Factor the band matrix of :func:`fill_band` in place as ``P A = L U`` (the
    multipliers of column ``k`` kept in rows ``k+1..k+kl``, LAPACK's order of row
    interchanges). Returns False at a pivot that is zero or not finite."""
    n = ab.shape[0]
    upper = kl + ku
    for k in range(n):
        last_row = min(n - 1, k + kl)
        pivot_row = k
        largest = abs(ab[k, kl])
        for i in range(k + 1, last_row + 1):
            value = abs(ab[i, kl + k - i])
            if value > largest:
                largest = value
                pivot_row = i
        piv[k] = pivot_row
        if not (largest > 0.0 and largest < 1e308):
            return False
        last_column = min(n - 1, k + upper)
        if pivot_row != k:
            for j in range(k, last_column + 1):
                a = ab[k, kl + j - k]
                ab[k, kl + j - k] = ab[pivot_row, kl + j - pivot_row]
                ab[pivot_row, kl + j - pivot_row] = a
        inverse = 1.0 / ab[k, kl]
        for i in range(k + 1, last_row + 1):
            factor = ab[i, kl + k - i] * inverse
            ab[i, kl + k - i] = factor
            if factor != 0.0:
                for j in range(k + 1, last_column + 1):
                    ab[i, kl + j - i] -= factor * ab[k, kl + j - k]
    return True


@njit(inline="always")
def band_lu_solve(ab, kl, ku, piv, b):
    """Solve ``A x = b`` in place in ``b`` from the factors of :func:`band_lu_factor`."""
    n = ab.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            b[k], b[p] = b[p], b[k]
        for i in range(k + 1, min(n - 1, k + kl) + 1):
            b[i] -= ab[i, kl + k - i] * b[k]
    upper = kl + ku
    for i in range(n - 1, -1, -1):
        total = b[i]
        for j in range(i + 1, min(n - 1, i + upper) + 1):
            total -= ab[i, kl + j - i] * b[j]
        b[i] = total / ab[i, kl]


@njit(inline="always")
def is_second_order(J):
    """Whether ``J`` is ``[[0, I], [A, B]]`` exactly (the first half of the states are
    positions whose derivatives are the second half, the speeds)."""
    n = J.shape[0]
    if n % 2:
        return False
    m = n // 2
    for i in range(m):
        for j in range(n):
            if J[i, j] != (1.0 if j == m + i else 0.0):
                return False
    return True
