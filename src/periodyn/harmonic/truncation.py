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


def _reach(S: int, *spectra: np.ndarray) -> np.ndarray:
    """Highest harmonic |k| per speed (S,) with an entry above _NEGLIGIBLE of that speed's
    largest, over spectra (S, 2K+1, ...) (index k+K)."""
    mags = sum(np.abs(x).reshape(S, x.shape[1], -1).max(axis=2) for x in spectra)  # (S, 2K+1)
    K = (mags.shape[1] - 1) // 2
    big = mags > _NEGLIGIBLE * mags.max(axis=1, keepdims=True)
    return np.where(big, np.abs(np.arange(2 * K + 1) - K), 0).max(axis=1)


def balance_truncation(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, force: np.ndarray,
                       q: np.ndarray, omega) -> np.ndarray:
    """Indicator (S,) of the HB solutions q (S, 2m+1, n) at speeds omega (S,) rad/s, with
    coefficient spectra mass (2K+1, n, n) or (S, 2K+1, n, n), damping and stiffness
    (S, 2K+1, n, n), force (S, 2K+1, n) (index k+K). NaN where q is not finite. Each speed's
    value depends on its own spectra only (the coefficient band and the forced harmonics
    are per speed), so a sweep's chunking does not change it by a bit."""
    w = np.atleast_1d(np.asarray(omega, float))
    S, H, n = q.shape
    m = (H - 1) // 2
    M = np.broadcast_to(mass, damping.shape)
    K = (damping.shape[1] - 1) // 2
    Kf = (force.shape[1] - 1) // 2
    band = _reach(S, M, damping, stiffness)              # (S,) coefficient band
    top = np.maximum(m + band, _reach(S, force))         # (S,) highest unbalanced harmonic
    scale = np.abs(q).reshape(S, -1).max(axis=1)
    out = np.zeros(S)
    for l in range(m + 1, int(top.max(initial=m)) + 1):
        R = force[:, Kf + l].copy() if l <= Kf else np.zeros((S, n), complex)
        for j in range(max(-m, l - int(band.max())), m + 1):
            coupled = (l - j <= band)[:, None, None]              # |l - j| within this speed's band
            jw = (j * w)[:, None, None]
            A = np.where(coupled, -jw ** 2 * M[:, K + l - j] + 1j * jw * damping[:, K + l - j]
                         + stiffness[:, K + l - j], 0.0)
            R -= np.einsum("sab,sb->sa", A, q[:, m + j])
        lw = (l * w)[:, None, None]
        D = -lw ** 2 * M[:, K] + 1j * lw * damping[:, K] + stiffness[:, K]
        try:
            est = np.abs(np.linalg.solve(D, R[..., None])[..., 0])
        except np.linalg.LinAlgError:  # one speed's mean system resonates at harmonic l: solve one by one
            est = np.array([_estimate(D[s], R[s]) for s in range(S)])
        out = np.where(l <= top, np.maximum(out, est.max(axis=1)), out)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(scale > 0, out / scale, 0.0)
    return np.where(np.isfinite(q).reshape(S, -1).all(axis=1), ratio, np.nan)


def _estimate(D: np.ndarray, R: np.ndarray) -> np.ndarray:
    """|D^-1 R| (n,) of one speed; inf where the mean system resonates at this harmonic."""
    try:
        return np.abs(np.linalg.solve(D, R))
    except np.linalg.LinAlgError:
        return np.full(R.shape, np.inf)


def balance_truncation_message(indicator: float, m: int, omega: float) -> str:
    """Why a periodic solution is unresolved, and the fix."""
    return (f"harmonic balance with harmonics = {m} leaves out harmonics at omega = {omega:.6g} rad/s of "
            f"{indicator:.2g} of the largest kept one (tolerance {BALANCE_TRUNCATION_TOL:g}): its amplitudes may be "
            "wrong; increase harmonics")
