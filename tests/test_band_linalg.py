"""compile/band_linalg.py: the banded Cholesky solves against numpy's dense solve of the
same matrix (an independent route)."""
import numpy as np

from mechdyn.compile.band_linalg import band_factor, band_solve, band_solve_rows


def tridiagonal_band():
    """[[4, 1, 0, 0], [1, 5, 2, 0], [0, 2, 6, 3], [0, 0, 3, 7]] by its lower band,
    ``m[i, d] = M[i, i - d]``; ``m`` a view at the start of a larger zeroed buffer (an
    index outside the band reads a zero, never stray memory)."""
    dense = np.array([[4.0, 1, 0, 0], [1, 5, 2, 0], [0, 2, 6, 3], [0, 0, 3, 7]])
    buffer = np.zeros(32)
    m = buffer[:8].reshape(4, 2)
    m[:, 0] = np.diag(dense)
    m[1:, 1] = np.diag(dense, -1)
    return dense, m


def test_band_solve_rows_solves_every_column_of_a_block_of_rows():
    dense, m = tridiagonal_band()
    band_factor(m, 1)
    rhs = np.array([[1.0, 0.0, 2.0], [2.0, 1.0, -1.0], [3.0, 0.0, 0.5], [4.0, -1.0, 1.0]])
    out = np.zeros((6, 3))
    out[2:] = rhs                                   # rows 2..5 of out hold B
    band_solve_rows(m, 1, out, 2)
    assert np.allclose(out[2:], np.linalg.solve(dense, rhs), rtol=1e-13, atol=0)
    assert not out[:2].any()                        # rows outside B untouched
    b = rhs[:, 0].copy()
    band_solve(m, 1, b)
    assert np.allclose(b, np.linalg.solve(dense, rhs[:, 0]), rtol=1e-13, atol=0)
