"""Fourier spectra of periodic sample series (pyFFTW, cached plans).

Conventions used throughout periodyn
------------------------------------
* One period is sampled at ``p`` equidistant angles ``theta_j = 2*pi*j/p``
  (``j = 0..p-1``), i.e. at times ``t_j = theta_j / omega``.
* A two-sided spectrum of a real periodic quantity ``x(theta)`` is an array ``c`` of
  shape ``(2K+1, ...)`` holding ``c_k`` for ``k = -K..K`` at index ``k + K``, with
  ``x(theta) = sum_k c_k exp(i k theta)`` and ``c_{-k} = conj(c_k)``.
* ``fourier_coefficients`` is the forward map (samples -> c), ``synthesize`` the
  inverse at arbitrary angles, ``to_samples`` the inverse at the ``p`` sample angles
  (zero padding, used for alternating frequency-time evaluation).
"""

from __future__ import annotations

import threading

import numpy as np
import pyfftw

__all__ = [
    "BAND_RTOL",
    "sample_angles",
    "harmonic_indices",
    "fourier_coefficients",
    "real_basis",
    "StackedSpectra",
    "to_samples",
    "synthesize",
    "half_synthesis",
    "spectral_tail",
    "min_samples",
]

#: coefficient harmonics below this fraction of the largest of their own spectrum are dropped
#: (the one band threshold of the Hill/HB operator and of output spectra)
BAND_RTOL = 1e-13

_THREADS = 1  # one FFT thread: parallelism is across speeds, not inside one transform
_plan_lock = threading.Lock()
_rfft_plans: dict[tuple, pyfftw.FFTW] = {}
_irfft_plans: dict[tuple, pyfftw.FFTW] = {}


def sample_angles(p: int) -> np.ndarray:
    """Sample angles ``2*pi*j/p``, shape (p,), rad."""
    return 2.0 * np.pi * np.arange(p) / p


def harmonic_indices(m: int) -> np.ndarray:
    """Harmonic indices ``-m..m``, shape (2m+1,)."""
    return np.arange(-m, m + 1)


def min_samples(harmonics: int, coefficient_harmonics: int = 0) -> int:
    """Smallest odd sample count free of aliasing for a product of a series with
    ``harmonics`` harmonics and coefficients with ``coefficient_harmonics``:
    ``p >= 2*(m + K) + 1``."""
    return 2 * (harmonics + coefficient_harmonics) + 1


def _rfft_plan(shape: tuple) -> pyfftw.FFTW:
    key = shape
    plan = _rfft_plans.get(key)
    if plan is None:
        with _plan_lock:
            a = pyfftw.empty_aligned(shape, dtype="float64")
            plan = pyfftw.builders.rfft(a, axis=0, threads=_THREADS, planner_effort="FFTW_ESTIMATE")
            _rfft_plans[key] = plan
    return plan


def _irfft_plan(shape: tuple, p: int) -> pyfftw.FFTW:
    key = (shape, p)
    plan = _irfft_plans.get(key)
    if plan is None:
        with _plan_lock:
            a = pyfftw.empty_aligned(shape, dtype="complex128")
            plan = pyfftw.builders.irfft(a, n=p, axis=0, threads=_THREADS, planner_effort="FFTW_ESTIMATE")
            _irfft_plans[key] = plan
    return plan


def fourier_coefficients(samples: np.ndarray, max_harmonic: int | None = None) -> np.ndarray:
    """Two-sided Fourier coefficients of real samples over one period.

    samples: (p, ...) real, sampled at ``sample_angles(p)``.
    max_harmonic: K; default the largest resolvable ``(p-1)//2``. A K above that is
    refused because those harmonics are not determined by p samples.
    Returns (2K+1, ...) complex, index ``k + K`` for ``k = -K..K``.
    """
    x = np.asarray(samples, dtype=float)
    p = x.shape[0]
    k_max = (p - 1) // 2
    if max_harmonic is None:
        max_harmonic = k_max
    if max_harmonic > k_max:
        raise ValueError(
            f"{p} samples resolve at most {k_max} harmonics, {max_harmonic} were asked for; "
            f"use at least {2 * max_harmonic + 1} samples"
        )
    shape = x.shape
    flat = x.reshape(p, -1)
    plan = _rfft_plan(flat.shape)
    plan.input_array[...] = flat  # copy into the plan's aligned buffer (any strides accepted)
    half = plan()[: max_harmonic + 1] / p
    out = np.empty((2 * max_harmonic + 1, flat.shape[1]), dtype=complex)
    out[max_harmonic:] = half
    out[:max_harmonic] = np.conj(half[:0:-1])
    return out.reshape((2 * max_harmonic + 1,) + shape[1:])


def to_samples(coefficients: np.ndarray, p: int) -> np.ndarray:
    """Real samples at ``sample_angles(p)`` of a two-sided spectrum (inverse of
    ``fourier_coefficients``). coefficients: (2K+1, ...), needs ``p >= 2K+1``.
    Returns (p, ...) real."""
    c = np.asarray(coefficients)
    K = (c.shape[0] - 1) // 2
    if p < 2 * K + 1:
        raise ValueError(f"{p} samples cannot represent {K} harmonics; use at least {2 * K + 1}")
    shape = c.shape
    flat = c.reshape(c.shape[0], -1)
    half = np.zeros((p // 2 + 1, flat.shape[1]), dtype=complex)
    half[: K + 1] = flat[K:]
    if p % 2 == 0 and K == p // 2:
        half[K] = 2 * half[K].real  # Nyquist term appears once
    plan = _irfft_plan(half.shape, p)
    plan.input_array[...] = half
    out = plan(normalise_idft=False).copy()
    return out.reshape((p,) + shape[1:])


def synthesize(coefficients: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Evaluate a two-sided spectrum (2K+1, ...) at angles theta (s,) -> (s, ...) real."""
    c = np.asarray(coefficients)
    K = (c.shape[0] - 1) // 2
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    basis = np.exp(1j * np.outer(theta, np.arange(-K, K + 1)))
    return np.tensordot(basis, c, axes=(1, 0)).real


def half_synthesis(harmonics: int, theta: np.ndarray) -> np.ndarray:
    """(s, 2(m+1)) real matrix giving the samples at angles theta (s,) of a real signal
    sum_a x_a e^(i a theta) from its harmonics a = 0..m stacked as [Re x; Im x] (x_-a =
    conj x_a: the samples are Re(x_0 + 2 sum_(a>0) x_a e^(i a theta)))."""
    a = np.arange(harmonics + 1)
    E = np.exp(1j * np.outer(np.atleast_1d(np.asarray(theta, dtype=float)), a)) * np.where(a > 0, 2.0, 1.0)
    return np.concatenate([E.real, -E.imag], axis=1)


def real_basis(harmonics: int, theta: np.ndarray) -> np.ndarray:
    """Real trigonometric basis (s, 2L+1) at angles theta (s,) rad: columns
    1, cos θ, sin θ, cos 2θ, sin 2θ, ..., cos Lθ, sin Lθ (the row layout of
    :class:`StackedSpectra`)."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    phase = np.outer(theta, np.arange(1, harmonics + 1))
    basis = np.empty((theta.size, 2 * harmonics + 1))
    basis[:, 0] = 1.0
    basis[:, 1::2], basis[:, 2::2] = np.cos(phase), np.sin(phase)
    return basis


class StackedSpectra:
    """Several real-signal spectra X_i (2K_i+1, ...) (l = -K_i..K_i) stacked as real cosine/sine
    coefficients, so that all their signals at any angles take one matrix product:
    ``values = real_basis(K, theta) @ rows`` with K = max K_i.

    Re sum_l X_l e^(ilθ) = X_0 + sum_{l>0} [cos lθ Re(X_l + X_-l) + sin lθ Im(X_-l - X_l)],
    exactly. ``rows``: (2K+1, total entries); :meth:`at` splits the product back into the
    spectra's shapes; :meth:`split` does that for values computed elsewhere (e.g. with a
    cached basis)."""

    def __init__(self, *spectra: np.ndarray):
        self.harmonics = max((np.shape(X)[0] - 1) // 2 for X in spectra)
        self.shapes = tuple(np.shape(X)[1:] for X in spectra)
        K = self.harmonics
        self.rows = np.zeros((2 * K + 1, sum(int(np.prod(s)) for s in self.shapes)))
        col = 0
        for X, shape in zip(spectra, self.shapes):
            X = np.asarray(X).reshape(np.shape(X)[0], -1)
            k, width = (X.shape[0] - 1) // 2, X.shape[1]
            block = self.rows[:, col: col + width]
            block[0] = X[k].real
            block[1: 2 * k + 1: 2] = (X[k + 1:] + X[k - 1:: -1][: k]).real
            block[2: 2 * k + 2: 2] = (X[k - 1:: -1][: k] - X[k + 1:]).imag
            col += width

    def split(self, values: np.ndarray) -> tuple[np.ndarray, ...]:
        """Values (s, total entries) split into one array (s, *shape_i) per spectrum."""
        out, col = [], 0
        for shape in self.shapes:
            width = int(np.prod(shape))
            out.append(values[:, col: col + width].reshape((values.shape[0],) + shape))
            col += width
        return tuple(out)

    def at(self, theta: np.ndarray) -> tuple[np.ndarray, ...]:
        """The real signals of every spectrum at angles theta (s,) rad: arrays (s, *shape_i)."""
        return self.split(real_basis(self.harmonics, theta) @ self.rows)


def spectral_tail(coefficients: np.ndarray) -> float:
    """Largest harmonic in the top quarter of the spectrum (at least the top one) relative
    to the largest harmonic, max-norm over all entries: small means resolved, no aliasing."""
    c = np.abs(np.asarray(coefficients))
    K = (c.shape[0] - 1) // 2
    if K == 0:
        return 0.0
    scale = c.max()
    if scale == 0.0:
        return 0.0
    width = max(1, (K + 3) // 4)
    top = max(c[:width].max(), c[-width:].max())
    return float(top / scale)
