"""Linear algebra of the Schur-complement correction of the stability method "reduced"
(:mod:`periodyn.stability.reduced`): the harmonic coefficient blocks of a Hill matrix, the
null vectors of the reduced Hill operator and the solves with the mean truncated blocks."""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

__all__ = ["harmonic_offsets", "truncated_solve", "null_vectors", "centred_null_vectors", "JACOBI_STEPS",
           "JACOBI_RTOL", "CENTRE_SLACK"]

# a null vector whose harmonic energy centroid is within this of half a harmonic from 0 is
# centred: on the line Im(lambda) = w/2 (a negative real multiplier) the centroid is +-1/2, and
# the shifts by -+1 only swap the two equally centred vectors
CENTRE_SLACK = 0.01
JACOBI_STEPS = 20  # Jacobi sweeps on the mean truncated blocks D_a before their dense solve
# relative residual of D_a z_a = r_a at which the sweeps stop: d_lambda is linear in z; at 1e-6
# it moved by at most 3.1e-8 of itself against 1e-12 (128 elements, 24 speeds), far inside the
# bound's 2 |d_lambda|, for two sweeps of 0.35 ms fewer
JACOBI_RTOL = 1e-6


def harmonic_offsets(X: np.ndarray, m: int) -> np.ndarray:
    """Coefficients X_(a-b) for a, b = -m..m from a spectrum (2K+1, ...), (2m+1, 2m+1, ...)."""
    K = (X.shape[0] - 1) // 2
    d = np.arange(-m, m + 1)[:, None] - np.arange(-m, m + 1)[None, :]
    out = np.zeros(d.shape + X.shape[1:], dtype=complex)
    inside = np.abs(d) <= K
    out[inside] = X[d[inside] + K]
    return out


def truncated_solve(A: np.ndarray, mass: np.ndarray | None, s: np.ndarray, r: np.ndarray) -> np.ndarray:
    """z (2m+1, h) with D_a z_a = r_a, D_a = s_a^2 Mh + s_a Ch + Kh, from the real mean
    truncated blocks side by side and transposed, A = [Mh^T, Ch^T, Kh^T] (h, 3h) with
    ``mass`` None, or A = [Ch^T, Kh^T] (h, 2h) with ``mass`` the diagonal (h,) of a diagonal
    Mh; s (2m+1,), r (2m+1, h): Jacobi sweeps on the diagonal (in mean-modal coordinates the blocks are
    diagonal up to the speed-dependent and non-proportional terms, small against the stiff
    truncated modes), O(m h^2) each, to JACOBI_RTOL; where they do not converge within
    JACOBI_STEPS, the dense solves (O(m h^3))."""
    h, rows = r.shape[1], r.shape[0]
    Ch, Kh = A[:, -2 * h: -h].T, A[:, -h:].T
    Mh = A[:, :h].T if mass is None else np.diag(mass)
    d = (s * s)[:, None] * np.diag(Mh) + s[:, None] * np.diag(Ch) + np.diag(Kh)
    z = r / d
    scale = np.linalg.norm(r)
    for _ in range(JACOBI_STEPS):
        Z = np.concatenate([z.real, z.imag]) @ A  # one real product for the blocks
        Z = Z[:rows] + 1j * Z[rows:]
        Mz = Z[:, :h] if mass is None else mass * z
        res = r - ((s * s)[:, None] * Mz + s[:, None] * Z[:, -2 * h: -h] + Z[:, -h:])
        if np.linalg.norm(res) <= JACOBI_RTOL * scale:
            return z
        z = z + res / d
    D = s[:, None, None] ** 2 * Mh[None] + s[:, None, None] * Ch[None] + Kh[None]
    return np.linalg.solve(D, r[..., None])[..., 0]


def null_vectors(Q: np.ndarray, iterations: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Right and left null vectors x, y (unit) of a nearly singular square Q (overwritten) by
    inverse iteration on one LU (Q x ~ 0, y^H Q ~ 0). Two iterations: a third moved d_lambda
    by at most 1.4e-12 of itself (16 and 128 elements, 24 speeds; one alone by 2.4e-7)."""
    lu = sla.lu_factor(Q, overwrite_a=True, check_finite=False)
    x = np.linspace(1.0, 2.0, Q.shape[0]) + 0j
    y = x.copy()
    for _ in range(iterations):
        x = sla.lu_solve(lu, x, check_finite=False)
        y = sla.lu_solve(lu, y, trans=2, check_finite=False)
        x, y = x / np.linalg.norm(x), y / np.linalg.norm(y)
    return x, y


def centred_null_vectors(M: np.ndarray, C: np.ndarray, K: np.ndarray, lam: complex, w: float, k: int):
    """(lam + i j w, x, y) with x, y (2m+1, k) the right and left null vectors of the reduced
    Hill operator Q_ll = (M s_b + C) s_b + K (s_b = lam + i b w per column harmonic b; M, C,
    K (N, N) at the speed w, N = (2m+1) k) whose right vector is centred in the harmonics
    (energy centroid within 1/2 + CENTRE_SLACK of 0): lam is shifted by the rounded
    centroid, at most three tries; None where none is centred."""
    m = (M.shape[0] // k - 1) // 2
    a = np.arange(-m, m + 1)
    for _ in range(3):
        sc = np.repeat(lam + 1j * a * w, k)
        Q = M * sc  # Q_ll = (M s + C) s + K, s per column
        Q += C
        Q *= sc
        Q += K
        x, y = null_vectors(Q)
        x, y = x.reshape(2 * m + 1, k), y.reshape(2 * m + 1, k)
        energy = (np.abs(x) ** 2).sum(axis=1)
        centroid = energy @ a / energy.sum()
        shift = int(np.rint(centroid)) if abs(centroid) > 0.5 + CENTRE_SLACK else 0
        if shift == 0:
            return lam, x, y
        lam = lam + 1j * shift * w
    return None
