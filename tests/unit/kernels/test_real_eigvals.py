"""Eigenvalues of small real matrices by the double-shift QR
(periodyn.kernels.solvers.real_eigvals) against known spectra and LAPACK dgeev."""

import numpy as np
import pytest
import scipy.linalg as sla

from periodyn.kernels.solvers.magnus_ladder import _eigvals
from periodyn.kernels.solvers.real_eigvals import LARGEST_QR, eigvals_small

RNG = np.random.default_rng(8)


def matched_error(got, ref):
    """Largest distance from each reference eigenvalue to the nearest computed one and back."""
    dist = np.abs(got[:, None] - ref[None, :])
    return max(dist.min(axis=0).max(), dist.min(axis=1).max())


def known_spectrum(d):
    """Q B Q^T with orthogonal Q and B block diagonal (2 x 2 rotation-scalings and reals):
    a monodromy-like matrix (moduli near 0.93, well conditioned) and its eigenvalues."""
    pairs = d // 2 - 1
    r, t = 0.93 + 0.01 * RNG.random(pairs), RNG.uniform(0.1, 3.0, pairs)
    B = np.zeros((d, d))
    for j in range(pairs):
        c, s = r[j] * np.cos(t[j]), r[j] * np.sin(t[j])
        B[2 * j: 2 * j + 2, 2 * j: 2 * j + 2] = [[c, -s], [s, c]]
    real = np.array([0.5, -0.9] + [0.7] * (d - 2 * pairs - 2))
    B[2 * pairs:, 2 * pairs:] = np.diag(real)
    Q = np.linalg.qr(RNG.standard_normal((d, d)))[0]
    lam = np.concatenate([r * np.exp(1j * t), r * np.exp(-1j * t), real])
    return Q @ B @ Q.T, lam


@pytest.mark.parametrize("d", [6, 80, 121, LARGEST_QR + 20])
def test_known_spectrum_and_dgeev_agree(d):
    X, lam = known_spectrum(d)
    got = eigvals_small(X)
    assert matched_error(got, lam) < 1e-13
    assert matched_error(got, _eigvals(X)) < 1e-13
    assert np.array_equal(np.sort_complex(got[got.imag > 0].conj()), np.sort_complex(got[got.imag < 0]))


def test_eigenvalues_isolated_by_balancing_are_kept():
    """Rows and columns that the balancing permutes off (a triangular frame around a full block)."""
    d = 90
    X = np.triu(RNG.standard_normal((d, d)))
    X[10:80, 10:80] = RNG.standard_normal((70, 70))
    ref = np.linalg.eigvals(X)
    got = eigvals_small(X)
    assert matched_error(got, ref) < 1e-10 * np.abs(ref).max()
    isolated = np.diag(X)[np.r_[:10, 80:90]]  # exactly, from the diagonal
    assert np.abs(got[:, None] - isolated[None, :]).min(axis=0).max() == 0.0


def test_monodromy_of_a_damped_chain():
    n = 40
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1) + np.diag(np.linspace(0.5, 1.5, n))
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -0.05 * np.eye(n)]])
    X = sla.expm(2.7 * A)
    lam = np.exp(2.7 * np.linalg.eigvals(A))
    assert matched_error(eigvals_small(X), lam) < 1e-12
