"""Whether a derived mass matrix is singular everywhere: a combination of coordinates
that moves no inertia is refused by name when the equations are derived (the start of a
run checks the matrix at the given values: :mod:`mechdyn.simulate.run_checks`).
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from mechdyn.errors import DerivationError

__all__ = ["check_regular"]


def check_regular(mass, q, name):
    """Refuse a mass matrix that is singular everywhere (a combination of coordinates
    that moves no inertia), tested at two random real configurations. A sample where
    an entry is not a finite real number (a root of a negative number for those
    parameter values) is no evidence: another is drawn, and with fewer than two real
    samples in :data:`_SAMPLES` draws nothing is refused (the start of a run checks the
    mass matrix at the given values: :func:`mechdyn.simulate.run_checks.check_mass`)."""
    n = mass.shape[0]
    if n < 2:
        return
    rng = np.random.default_rng(12345)
    free = sorted(mass.free_symbols, key=str)
    smallest = []
    for _ in range(_SAMPLES):
        values = {s: sp.Float(rng.uniform(-3, 3) if s in q else rng.uniform(0.5, 1.5))
                  for s in free}
        numeric = _real_matrix(mass, values)
        if numeric is None:
            continue
        smallest.append(_smallest_singular(numeric))
        if len(smallest) == 2:
            break
    if len(smallest) == 2 and all(ratio < 1e-12 for ratio, _ in smallest):
        vector = smallest[0][1] / np.max(np.abs(smallest[0][1]))
        combination = " + ".join(f"{c:.3g}*{qi}" for c, qi in zip(vector, q) if abs(c) > 1e-9)
        raise DerivationError(
            f"mechanism {name!r}: the mass matrix is singular: the motion "
            f"{combination} moves no mass or inertia (coordinates that always move "
            "together need one coordinate, or a link that moves with the difference)")


_SAMPLES = 20           # draws for the two real samples of the regularity check


def _smallest_singular(matrix) -> tuple:
    """``(sigma_min / sigma_max, its right singular vector)`` of a mass matrix: from the
    band's extreme eigenvalues where the matrix is symmetric, narrow and positive
    semidefinite (O(n b^2): a chain of a thousand bodies in milliseconds), else by SVD.

    >>> ratio, vector = _smallest_singular(np.array([[2.0, 1.0], [1.0, 0.5]]))
    >>> float(round(ratio, 12)), np.round(np.abs(vector), 4).tolist()
    (0.0, [0.4472, 0.8944])
    """
    n = len(matrix)
    rows, columns = np.nonzero(matrix)
    width = int(np.max(np.abs(rows - columns), initial=0))
    if 4 * width < n and np.array_equal(matrix, matrix.T):
        from scipy.linalg import eig_banded
        band = np.zeros((width + 1, n))
        for k in range(width + 1):
            band[k, :n - k] = np.diagonal(matrix, -k)
        low, vectors = eig_banded(band, lower=True, select="i", select_range=(0, 0))
        high = eig_banded(band, lower=True, eigvals_only=True, select="i",
                          select_range=(n - 1, n - 1))
        if low[0] >= 0.0:
            return low[0] / max(high[0], 1e-300), vectors[:, 0]
    _, singular, vt = np.linalg.svd(matrix)
    return singular[-1] / max(singular[0], 1e-300), vt[-1]


def _real_matrix(mass, values):
    """``mass`` at ``values`` as floats, or None where an entry is not finite and real."""
    numeric = np.zeros(mass.shape)
    for (i, j), entry in mass.todok().items():        # the non-zero entries
        value = complex(sp.N(entry.xreplace(values)))
        if not (np.isfinite(value) and abs(value.imag) <= 1e-12 * abs(value.real)):
            return None
        numeric[i, j] = value.real
    return numeric
