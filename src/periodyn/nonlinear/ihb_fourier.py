"""Real Fourier layout of the IHB unknowns and the FFT-built coefficient blocks.

Per coordinate the ``2H+1`` real coefficients are ``[a_0, a_1..a_H, b_1..b_H]`` of
``x(tau) = a_0 + sum_k a_k cos(k tau) + b_k sin(k tau)``, ``tau = Omega t`` with
``Omega = omega / nu`` (nu = 1 for period T = 2 pi / omega, nu = 2 for a period-doubled
orbit). Conversions to the two-sided spectra of ``periodyn.numerics.spectra`` (index k + H) are
exact; transforms go through pyFFTW there.
"""

from __future__ import annotations

import numpy as np

from ..numerics.spectra import fourier_coefficients, to_samples

__all__ = ["real_to_complex", "complex_to_real", "derivative_matrix", "product_blocks", "spectrum_blocks",
           "real_samples", "real_coefficients"]


def real_to_complex(a: np.ndarray) -> np.ndarray:
    """(2H+1, ...) real layout -> (2H+1, ...) two-sided complex, index k + H."""
    H = (a.shape[0] - 1) // 2
    c = np.empty(a.shape, dtype=complex)
    c[H] = a[0]
    half = 0.5 * (a[1:H + 1] - 1j * a[H + 1:])
    c[H + 1:] = half
    c[:H] = np.conj(half[::-1])
    return c


def complex_to_real(c: np.ndarray, H: int) -> np.ndarray:
    """Two-sided (2K+1, ...) with K >= H -> (2H+1, ...) real layout (truncated to H)."""
    K = (c.shape[0] - 1) // 2
    a = np.empty((2 * H + 1,) + c.shape[1:])
    a[0] = c[K].real
    a[1:H + 1] = 2.0 * c[K + 1:K + H + 1].real
    a[H + 1:] = -2.0 * c[K + 1:K + H + 1].imag
    return a


def derivative_matrix(H: int) -> np.ndarray:
    """d/dtau in the real layout, (2H+1, 2H+1): a_k' = k b_k, b_k' = -k a_k."""
    D = np.zeros((2 * H + 1, 2 * H + 1))
    k = np.arange(1, H + 1)
    D[k, H + k] = k
    D[H + k, k] = -k
    return D


def real_samples(a: np.ndarray, p: int) -> np.ndarray:
    """Samples at tau_j = 2 pi j / p of a real-layout series (2H+1, ...) -> (p, ...)."""
    return to_samples(real_to_complex(a), p)


def real_coefficients(samples: np.ndarray, H: int) -> np.ndarray:
    """Galerkin (Fourier) coefficients of samples (p, ...) in the real layout (2H+1, ...)."""
    return complex_to_real(fourier_coefficients(samples, H), H)


def product_blocks(samples: np.ndarray, H: int) -> np.ndarray:
    """Coefficient blocks of multiplication by sampled functions A_e(tau).

    samples: (p, E) real with p >= 4H+1 (the spectra of A up to harmonic 2H are needed
    exactly). Returns G (E, 2H+1, 2H+1): real-layout coefficients of ``A_e x`` are
    ``G[e] @ x`` for a real-layout x with H harmonics (Galerkin projection onto H).
    Built from the FFT spectra A_d, d = -2H..2H: with ``C_k = sum_l A_{k-l} X_l``,
    dC_k/da_0 = A_k, dC_k/da_l = (A_{k-l} + A_{k+l})/2, dC_k/db_l = i (A_{k+l} - A_{k-l})/2.
    """
    return spectrum_blocks(fourier_coefficients(samples, 2 * H).T, H)


def spectrum_blocks(A: np.ndarray, H: int) -> np.ndarray:
    """:func:`product_blocks` from the two-sided spectra A (E, 4H+1), index d + 2H."""
    E = A.shape[0]
    k = np.arange(H + 1)[:, None]
    l = np.arange(1, H + 1)[None, :]
    Am = A[:, k - l + 2 * H]
    Ap = A[:, k + l + 2 * H]
    dC = np.empty((E, H + 1, 2 * H + 1), dtype=complex)
    dC[:, :, 0] = A[:, np.arange(H + 1) + 2 * H]
    dC[:, :, 1:H + 1] = 0.5 * (Am + Ap)
    dC[:, :, H + 1:] = 0.5j * (Ap - Am)
    G = np.empty((E, 2 * H + 1, 2 * H + 1))
    G[:, 0] = dC[:, 0].real
    G[:, 1:H + 1] = 2.0 * dC[:, 1:].real
    G[:, H + 1:] = -2.0 * dC[:, 1:].imag
    return G
