"""The jitted banded solver against dense LAPACK (NumPy) on matrices that need pivoting."""

import numpy as np
import pytest

from periodyn.kernels.solvers.banded import banded_matvec, banded_solve_batch

RNG = np.random.default_rng(3)


def dense_from_band(ab):
    u, N = (ab.shape[0] - 1) // 2, ab.shape[1]
    A = np.zeros((N, N), dtype=complex)
    for i in range(N):
        for j in range(max(0, i - u), min(N, i + u + 1)):
            A[i, j] = ab[u + i - j, j]
    return A


@pytest.mark.parametrize("N,u", [(1, 0), (7, 1), (13, 3), (40, 6), (25, 24)])
def test_banded_solve_matches_dense(N, u):
    S = 4
    ab = RNG.standard_normal((S, 2 * u + 1, N)) + 1j * RNG.standard_normal((S, 2 * u + 1, N))
    ab[:, u] *= 1e-3  # weak diagonal: row interchanges are needed
    b = RNG.standard_normal((S, N)) + 1j * RNG.standard_normal((S, N))
    x, residual, failed = np.empty_like(b), np.empty(S), np.zeros(S, dtype=np.int64)
    banded_solve_batch(ab, b, x, residual, failed)
    assert not failed.any()
    for s in range(S):
        A = dense_from_band(ab[s])
        ref = np.linalg.solve(A, b[s])
        np.testing.assert_allclose(x[s], ref, atol=1e-10 * np.abs(ref).max())
        assert residual[s] == pytest.approx(np.linalg.norm(A @ x[s] - b[s]), rel=1e-6, abs=1e-13)
        out = np.empty(N, dtype=complex)
        banded_matvec(ab[s], x[s], out)
        np.testing.assert_allclose(out, A @ x[s], atol=1e-12 * np.abs(out).max())


def test_singular_matrix_is_reported_not_solved():
    N, u = 6, 1
    ab = RNG.standard_normal((1, 2 * u + 1, N)) + 0j
    ab[0, :, 2] = 0.0  # column 2 is zero
    b = np.ones((1, N), dtype=complex)
    x, residual, failed = np.empty_like(b), np.empty(1), np.zeros(1, dtype=np.int64)
    banded_solve_batch(ab, b, x, residual, failed)
    assert failed[0] == 3 and np.isnan(residual[0])
