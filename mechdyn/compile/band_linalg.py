"""Cholesky factorisation and solves of a symmetric banded matrix, compiled with numba, for
the generated code of large models (:mod:`mechdyn.compile.mass_solve`).

The matrix is held by its lower band, ``m[i, d] = M[i, i - d]`` for ``d = 0..bw`` (the
half-bandwidth ``bw``: ``M[i, j] = 0`` where ``|i - j| > bw``); ``bw = n - 1`` is the
dense matrix. Factoring costs ``n bw^2 / 2`` multiplications, a solve ``2 n bw``; the
factor keeps the band. A pivot that is not positive (``M`` not positive definite) makes
it NaN, so every result computed from the factor is NaN and a solver rejects the step.

>>> import numpy as np
>>> m = np.array([[4.0, 0.0], [5.0, 2.0], [5.0, 2.0]])      # tridiagonal [[4,2,0],[2,5,2],[0,2,5]]
>>> band_factor(m, 1)
>>> b = np.array([6.0, 9.0, 7.0]); band_solve(m, 1, b); b.tolist()
[1.0, 1.0, 1.0]
"""
from math import nan, sqrt

from numba import njit

from mechdyn.numba_cache import CACHED

__all__ = ["band_factor", "band_solve", "band_solve_rows", "band_view"]


@njit(cache=CACHED, error_model="numpy")
def band_factor(m, bw):
    """Factor ``M = L L'`` in place: ``m[i, d]`` becomes ``L[i, i - d]``."""
    n = m.shape[0]
    for i in range(n):
        first = max(0, i - bw)
        for j in range(first, i):
            total = m[i, i - j]
            for k in range(first, j):
                total -= m[i, i - k] * m[j, j - k]
            m[i, i - j] = total / m[j, 0]
        total = m[i, 0]
        for k in range(first, i):
            total -= m[i, i - k] * m[i, i - k]
        m[i, 0] = sqrt(total) if total > 0.0 else nan


@njit(cache=CACHED, error_model="numpy")
def band_solve(m, bw, b):
    """Solve ``L L' x = b`` in place in ``b`` with the factor of :func:`band_factor`."""
    n = m.shape[0]
    for i in range(n):
        total = b[i]
        for k in range(max(0, i - bw), i):
            total -= m[i, i - k] * b[k]
        b[i] = total / m[i, 0]
    for i in range(n - 1, -1, -1):
        total = b[i]
        for k in range(i + 1, min(n, i + bw + 1)):
            total -= m[k, k - i] * b[k]
        b[i] = total / m[i, 0]


@njit(cache=CACHED, error_model="numpy")
def band_solve_rows(m, bw, out, first):
    """Solve ``L L' X = B`` in place for ``B = out[first:first + n, :]`` (every column),
    a row of ``B`` at a time (contiguous: the columns are updated together)."""
    n = m.shape[0]
    for i in range(n):
        for k in range(max(0, i - bw), i):
            _subtract_row(out, first + i, first + k, m[i, i - k])
        _divide_row(out, first + i, m[i, 0])
    for i in range(n - 1, -1, -1):
        for k in range(i + 1, min(n, i + bw + 1)):
            _subtract_row(out, first + i, first + k, m[k, k - i])
        _divide_row(out, first + i, m[i, 0])


@njit(inline="always")
def _subtract_row(out, target, source, factor):
    for c in range(out.shape[1]):
        out[target, c] -= factor * out[source, c]


@njit(inline="always")
def _divide_row(out, row, pivot):
    for c in range(out.shape[1]):
        out[row, c] /= pivot


@njit(cache=CACHED)
def band_view(p, first, n, bw):
    """The factored band ``n x (bw + 1)`` stored in ``p`` from ``first`` (a constant mass
    matrix factored once per parameter vector), viewed without a copy."""
    return p[first:first + n * (bw + 1)].reshape((n, bw + 1))
