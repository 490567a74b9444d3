"""What the method choice measures of a Jacobian's spectrum: the fastest mode (spectral
radius), the most damped one and the slow end (the magnitudes nearest zero).

Up to ``DENSE_LIMIT`` states every eigenvalue is computed (``numpy.linalg.eigvals``).
A larger model (a chain of 100 discs: a 200 x 200 Jacobian, 10-25 ms for its
eigenvalues, more than its whole run) is measured by Krylov estimates on the sparse
Jacobian, each a few dozen sparse products or solves (well under a millisecond):

- the fast end by Arnoldi's method on ``J`` (the Ritz values of its outer eigenvalues),
  with the positions scaled by ``sqrt(|df/dq|)`` (a similarity: the same eigenvalues,
  but a near-normal matrix, so the Ritz values stay inside the spectrum);
- the slow end by Arnoldi's method on ``(J - s I)^-1`` (a sparse LU) with a small
  shift ``s``: the eigenvalues nearest zero, rigid-body (zero) modes among them.

A Ritz value approaches its eigenvalue from inside the spectrum, so the estimates
err towards "not stiff"; the compiled kernels' and :class:`StiffnessMonitor`'s
stiffness tests catch a problem that turns out stiffer during the run.

>>> import numpy as np
>>> chain = np.zeros((200, 200))                 # 100 unit discs, unit springs
>>> chain[range(100), range(100, 200)] = 1.0
>>> stiffness = 2 * np.eye(100) - np.eye(100, k=1) - np.eye(100, k=-1)
>>> stiffness[0, 0] = stiffness[-1, -1] = 1.0
>>> chain[100:, :100] = -stiffness
>>> fastest, damped, slow = measures(chain)     # exact: 2 sin(99 pi/200) = 1.99975, 0
>>> round(fastest, 2), round(damped, 6)
(1.96, 0.0)
>>> zero, _, first = np.sort(np.abs(slow))[:3]   # rigid mode, 2 sin(pi/200) = 0.0314149
>>> bool(zero < 1e-7), round(float(first), 5)
(True, 0.03141)
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["DENSE_LIMIT", "measures", "spectral_radius"]

DENSE_LIMIT = 64          # states up to which every eigenvalue is computed
_OUTER_STEPS = 16         # Arnoldi steps for the fast end
_INNER_STEPS = 10         # ... and for the slow end (on the shifted inverse)
_SHIFT = 1e-5             # the slow end's shift, relative to the fastest magnitude


def measures(jacobian) -> tuple:
    """``(fastest, damped, slow)``: the largest eigenvalue magnitude, the largest
    ``-Re(lambda)`` (0 when none is negative) and eigenvalues at the slow end (every
    eigenvalue up to ``DENSE_LIMIT`` states, else estimates of those nearest zero).
    ``jacobian``: an array, or a ``scipy.sparse`` matrix of a large model."""
    if len(_shape(jacobian)) and _shape(jacobian)[0] <= DENSE_LIMIT:
        return _dense(np.asarray(jacobian, dtype=float))
    try:
        return _estimates(jacobian)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):     # overflow: in full
        return _dense(_array(jacobian))


def _estimates(jacobian) -> tuple:
    from scipy.sparse.linalg import splu
    rows, columns, values = _balanced(jacobian)
    size = _shape(jacobian)[0]
    start = _start(size)
    outer = _ritz_values(_csc(rows, columns, values, size).dot, start, _OUTER_STEPS)
    fastest = float(np.abs(outer).max(initial=0.0))
    damped = float(np.max(-outer.real, initial=0.0))
    shift = -_SHIFT * max(fastest, 1.0)
    diagonal = np.arange(size)
    shifted = _csc(np.concatenate([rows, diagonal]), np.concatenate([columns, diagonal]),
                   np.concatenate([values, np.full(size, -shift)]), size)
    try:
        factor = splu(shifted)
    except RuntimeError:                   # the shift is an eigenvalue (exactly singular)
        return _dense(_array(jacobian))
    inverse = _ritz_values(factor.solve, start, _INNER_STEPS)
    if not (np.all(np.isfinite(outer)) and np.all(np.isfinite(inverse))):
        return _dense(_array(jacobian))    # an estimate lost to overflow: measure in full
    return fastest, damped, shift + 1.0 / inverse[inverse != 0]


def spectral_radius(jacobian) -> float:
    """The largest eigenvalue magnitude: in full up to ``DENSE_LIMIT`` states, else the
    Arnoldi estimate of :func:`measures`."""
    size = _shape(jacobian)[0]
    if size <= DENSE_LIMIT:
        return float(np.max(np.abs(np.linalg.eigvals(np.asarray(jacobian, dtype=float)))))
    outer = _ritz_values(_csc(*_balanced(jacobian), size).dot, _start(size), _OUTER_STEPS)
    return float(np.abs(outer).max(initial=0.0))


def _dense(jacobian) -> tuple:
    eigenvalues = np.linalg.eigvals(jacobian)
    magnitude = np.abs(eigenvalues)
    return (magnitude.max(initial=0.0), np.max(-eigenvalues.real, initial=0.0),
            eigenvalues)


def _shape(jacobian):
    return jacobian.shape if hasattr(jacobian, "shape") else np.shape(jacobian)


def _array(jacobian):
    return jacobian.toarray() if hasattr(jacobian, "toarray") else np.asarray(jacobian,
                                                                            dtype=float)


def _csc(rows, columns, values, size):
    from scipy.sparse import csc_matrix
    return csc_matrix((values, (rows, columns)), shape=(size, size))


def _balanced(jacobian):
    """The non-zero entries ``(rows, columns, values)`` of ``D J D^-1``, ``D`` scaling
    the positions (the first half of the states) by ``sqrt`` of the largest row sum of
    ``|df/dq|`` (the order of the fastest frequency squared)."""
    if hasattr(jacobian, "tocoo"):
        entries = jacobian.tocoo()
        rows, columns, values = entries.row, entries.col, entries.data.astype(float)
    else:
        jacobian = np.asarray(jacobian, dtype=float)
        rows, columns = np.nonzero(jacobian)
        values = jacobian[rows, columns]
    size = _shape(jacobian)[0]
    n = size // 2
    block = (rows >= n) & (columns < n)
    rate = float(np.bincount(rows[block], np.abs(values[block]), size).max(initial=0.0))
    if size % 2 or not 0.0 < rate < np.inf:
        return rows, columns, values
    scale = np.ones(size)
    scale[:n] = np.sqrt(rate)
    return rows, columns, values * scale[rows] / scale[columns]


def _start(size):
    """A fixed start vector (the same call gives the same answer)."""
    return 1.0 + np.arange(size) / size


def _ritz_values(operator, start, steps):
    """The eigenvalues of the Hessenberg matrix of ``steps`` Arnoldi steps of
    ``operator`` from ``start`` (Gram-Schmidt twice; stops early on an invariant
    subspace)."""
    size = len(start)
    steps = min(steps, size)
    basis = np.empty((steps + 1, size))
    hessenberg = np.zeros((steps + 1, steps))
    basis[0] = start / math.sqrt(start @ start)
    for j in range(steps):
        w = operator(basis[j])
        done = basis[:j + 1]
        h = done @ w
        w -= h @ done
        again = done @ w
        w -= again @ done
        h += again
        hessenberg[:j + 1, j] = h
        norm = math.sqrt(w @ w)
        if not norm > 1e-12 * max(h.max(), -h.min(), 1e-300):
            return np.linalg.eigvals(hessenberg[:j + 1, :j + 1])
        hessenberg[j + 1, j] = norm
        np.multiply(w, 1.0 / norm, out=basis[j + 1])
    return np.linalg.eigvals(hessenberg[:steps, :steps])
