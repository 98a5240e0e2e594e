"""Truncation indicator of a harmonic-balance solution: the harmonics it leaves out.

The Galerkin projection keeps the equations of harmonics |l| <= m only. Put the solution
q_j (j = -m..m) into the full equations M q'' + C q' + K q = f with coefficient harmonics
|k| <= K: the harmonics l = m+1..m+K of the equations are not balanced, with residual

    R_l = f_l - sum_j [-(j w)^2 M_{l-j} + i j w C_{l-j} + K_{l-j}] q_j.

One step of the block-Jacobi iteration on the missing harmonics estimates them,
q_l ~ D_l^-1 R_l with D_l = -(l w)^2 M_0 + i l w C_0 + K_0 (the mean system), and the
indicator is the largest |q_l| relative to the largest kept |q_j| (max-norm over the
coordinates). Small means the m harmonics resolve the response; with constant
coefficients it is 0. A sweep records it per point (``balance_truncation``) and warns
(:class:`BalanceTruncationWarning`) where it exceeds :data:`BALANCE_TRUNCATION_TOL`.
"""

from __future__ import annotations

import numpy as np

__all__ = ["BALANCE_TRUNCATION_TOL", "BalanceTruncationWarning", "balance_truncation", "balance_truncation_message"]

#: indicator above which a periodic solution is called unresolved (amplitudes then differ
#: from the integrated orbit by up to about this fraction or more: benchmarks/property_run.py)
BALANCE_TRUNCATION_TOL = 1e-2
_NEGLIGIBLE = 1e-13  # coefficient harmonics below this fraction of the largest are left out


class BalanceTruncationWarning(UserWarning):
    """A harmonic-balance solution leaves out harmonics of the size of those it keeps."""


def _band(*spectra: np.ndarray) -> int:
    """Highest coefficient harmonic K with an entry above _NEGLIGIBLE of the largest."""
    K = (spectra[0].shape[-3] - 1) // 2
    mags = sum(np.abs(s).reshape(-1, 2 * K + 1, *s.shape[-2:]).max(axis=(0, 2, 3)) for s in spectra)
    big = np.flatnonzero(mags > _NEGLIGIBLE * mags.max(initial=0.0))
    return int(np.abs(big - K).max(initial=0))


def balance_truncation(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, force: np.ndarray,
                       q: np.ndarray, omega) -> np.ndarray:
    """Indicator (S,) of the HB solutions q (S, 2m+1, n) at speeds omega (S,) rad/s, with
    coefficient spectra mass (2K+1, n, n) or (S, 2K+1, n, n), damping and stiffness
    (S, 2K+1, n, n), force (S, 2K+1, n) (index k+K). NaN where q is not finite."""
    w = np.atleast_1d(np.asarray(omega, float))
    S, H, n = q.shape
    m = (H - 1) // 2
    M = np.broadcast_to(mass, damping.shape)
    K = (damping.shape[1] - 1) // 2
    band = _band(M, damping, stiffness)
    scale = np.abs(q).reshape(S, -1).max(axis=1)
    Kf = (force.shape[1] - 1) // 2
    fmag = np.abs(force).max(axis=(0, 2))
    forced = np.flatnonzero(fmag > _NEGLIGIBLE * fmag.max(initial=0.0))
    out = np.zeros(S)
    for l in range(m + 1, max(m + band, int(np.abs(forced - Kf).max(initial=0))) + 1):
        R = force[:, Kf + l].copy() if l <= Kf else np.zeros((S, n), complex)
        for j in range(max(-m, l - band), m + 1 if l - m <= band else -m):
            jw = (j * w)[:, None, None]
            A = -jw ** 2 * M[:, K + l - j] + 1j * jw * damping[:, K + l - j] + stiffness[:, K + l - j]
            R -= np.einsum("sab,sb->sa", A, q[:, m + j])
        lw = (l * w)[:, None, None]
        D = -lw ** 2 * M[:, K] + 1j * lw * damping[:, K] + stiffness[:, K]
        try:
            est = np.linalg.solve(D, R[..., None])[..., 0]
        except np.linalg.LinAlgError:  # the mean system resonates at harmonic l: nothing resolves it
            est = np.full((S, n), np.inf)
        out = np.maximum(out, np.abs(est).max(axis=1))
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(scale > 0, out / scale, 0.0)
    return np.where(np.isfinite(q).reshape(S, -1).all(axis=1), ratio, np.nan)


def balance_truncation_message(indicator: float, m: int, omega: float) -> str:
    """Why a periodic solution is unresolved, and the fix."""
    return (f"harmonic balance with harmonics = {m} leaves out harmonics at omega = {omega:.6g} rad/s of "
            f"{indicator:.2g} of the largest kept one (tolerance {BALANCE_TRUNCATION_TOL:g}): its amplitudes may be "
            "wrong; increase harmonics")
