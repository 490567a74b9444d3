"""Small dense LU decomposition with partial pivoting, and the stage sums of the
Runge-Kutta and Rosenbrock steps, compiled with numba.

Own code rather than ``np.linalg``: LAPACK would pull scipy.linalg into the kernel's
import and make results depend on the BLAS build's rounding. The matrices of mechdyn's
models are small (tens of states), where a plain triple loop is as fast as LAPACK.

>>> import numpy as np
>>> a = np.array([[0.0, 2.0], [4.0, 1.0]]); piv = np.zeros(2, np.int64)
>>> lu_factor(a, piv)
True
>>> b = np.array([2.0, 9.0]); lu_solve(a, piv, b); b.tolist()
[2.0, 1.0]
>>> stage_sum(np.array([0.5, 2.0, 9.0]), np.array([[2.0, 0.0], [3.0, 1.0]]), 0, 2)
7.0
"""
from numba import njit


@njit(inline="always")
def lu_factor(a, piv):
    """Factor the square ``a`` in place as P A = L U (unit lower L); pivots into ``piv``.

    Returns False when a pivot is exactly zero or not finite (singular or poisoned
    matrix); ``a`` is then unusable.
    """
    n = a.shape[0]
    for k in range(n):
        pivot_row = k
        largest = abs(a[k, k])
        for i in range(k + 1, n):
            if abs(a[i, k]) > largest:
                largest = abs(a[i, k])
                pivot_row = i
        piv[k] = pivot_row
        if not (largest > 0.0 and largest < 1e308):
            return False
        if pivot_row != k:
            for j in range(n):
                a[k, j], a[pivot_row, j] = a[pivot_row, j], a[k, j]
        inverse = 1.0 / a[k, k]
        for i in range(k + 1, n):
            factor = a[i, k] * inverse
            a[i, k] = factor
            if factor != 0.0:
                for j in range(k + 1, n):
                    a[i, j] -= factor * a[k, j]
    return True


@njit(inline="always")
def lu_solve(lu, piv, b):
    """Solve A x = b in place in ``b`` from the factors of :func:`lu_factor`."""
    n = lu.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            b[k], b[p] = b[p], b[k]
    for i in range(n):
        total = b[i]
        for j in range(i):
            total -= lu[i, j] * b[j]
        b[i] = total
    for i in range(n - 1, -1, -1):
        total = b[i]
        for j in range(i + 1, n):
            total -= lu[i, j] * b[j]
        b[i] = total / lu[i, i]


@njit(inline="always")
def stage_sum(weights, ks, i, count):
    """``sum_j weights[j] ks[j, i]`` over the first ``count`` rows (stages) of ``ks``."""
    total = 0.0
    for j in range(count):
        total += weights[j] * ks[j, i]
    return total
