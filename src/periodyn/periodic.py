"""The periodic solution: one result type for harmonic balance (linear), EGA-IHB and shooting.

Fourier convention (the one used everywhere in periodyn): a periodic signal of period
``T_orbit = 2 pi nu / omega`` (nu = ``subharmonic``: 1 for a T-periodic orbit, 2 for a
period-doubled one) is stored as complex two-sided harmonics ``c`` of shape (2m+1, n),
row ``l + m`` for l = -m..m, with base frequency ``Omega = omega / nu``:

    x(t) = sum_{l=-m..m} c_l exp(i l Omega t),   c_{-l} = conj(c_l) for real x.

Amplitudes are half peak-to-peak, taken from the extrema of the trigonometric series
(located on a grid, refined by Newton steps on its derivative), so they are as accurate
as the harmonics themselves.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from .kernels.solvers.harmonic import half_range as _half_range_kernel
from .numerics.spectra import BAND_RTOL, spectral_tail, synthesize, to_samples

__all__ = ["PeriodicSolution", "half_range_and_mean", "output_spectrum"]


def half_range_and_mean(coefficients: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Half peak-to-peak and mean of real periodic signals from spectra (2M+1, r).

    Extrema are located on a grid of 8(2M+1) >= 64 angles and refined by Newton steps on
    the derivative of the Fourier series (jitted kernel)."""
    c = np.ascontiguousarray(coefficients, dtype=complex)
    M = (c.shape[0] - 1) // 2
    half, mean = np.zeros(c.shape[1]), np.zeros(c.shape[1])
    if M == 0:
        return half, c[0].real.copy()
    grid = to_samples(c, max(64, 8 * (2 * M + 1)))
    _half_range_kernel(c, grid, half, mean)
    return half, mean


def output_spectrum(G: np.ndarray, harmonics: np.ndarray) -> np.ndarray:
    """Spectrum of y = G(t) q(t): G (2KG+1, n_out, n), q (..., 2m+1, n) ->
    (..., 2(m+KG')+1, n_out), with KG' the significant band of G (the product is exact,
    no aliasing); leading axes (e.g. speeds) are carried along."""
    KG = (G.shape[0] - 1) // 2
    mag = np.abs(G).reshape(G.shape[0], -1).max(axis=1)
    big = np.nonzero(mag > BAND_RTOL * max(mag.max(), np.finfo(float).tiny))[0]
    kg = int(np.abs(big - KG).max()) if big.size else 0
    G = G[KG - kg: KG + kg + 1]
    m = (harmonics.shape[-2] - 1) // 2
    out = np.zeros(harmonics.shape[:-2] + (2 * (m + kg) + 1, G.shape[1]), dtype=complex)
    for j in range(2 * kg + 1):  # y_{l + (j-kg)} += G_{j-kg} q_l
        out[..., j: j + 2 * m + 1, :] += harmonics @ G[j].T
    return out


@dataclass(frozen=True, eq=False)
class PeriodicSolution:
    """Periodic solution ``q(t) = sum_l harmonics[l+m] exp(i l omega t / subharmonic)``.

    omega: driving frequency, rad/s; harmonics: (2m+1, n) complex, l = -m..m (module
    docstring). output_spectrum: (2M+1, n_out) complex spectrum of outputs y = G(t) q(t)
    (M = m + band of G), or None when the outputs are the coordinates. residual: final
    residual norm (HB: ||H x - f|| / ||f||; IHB, shooting: max-norm of the equations in SI
    units); form: HB balance form ("direct"|"inverse-mass"), None otherwise; iterations:
    Newton steps (0 for the linear solve); method: "hb", "ihb" or "shooting"; subharmonic:
    nu (orbit period 2 pi nu / omega); lambda_harmonics: (2m+1, n_c) constraint forces of a
    DAE (N or N m), None otherwise; stability: the orbit's FloquetExponents, or None when
    not computed; parameters: model parameters the solution belongs to;
    discretization_error: of a fixed-step shooting orbit (``shooting(...,
    integrator="implicit")``), the Richardson estimate of the relative error of its N-step harmonics,
    a bound of the error of the extrapolated harmonics it returns
    (:mod:`periodyn.nonlinear.implicit`); None for the other methods.
    """

    omega: float
    harmonics: np.ndarray
    output_spectrum: np.ndarray | None
    coordinate_names: tuple[str, ...]
    output_names: tuple[str, ...]
    residual: float
    form: str | None = None
    iterations: int = 0
    method: str = "hb"
    subharmonic: int = 1
    lambda_harmonics: np.ndarray | None = None
    constraint_names: tuple[str, ...] = ()
    stability: Any = None
    parameters: Mapping[str, float] = field(default_factory=dict)
    discretization_error: float | None = None

    @property
    def m(self) -> int:
        """Number of harmonics."""
        return (self.harmonics.shape[0] - 1) // 2

    @property
    def base_frequency(self) -> float:
        """Omega = omega / subharmonic, rad/s."""
        return self.omega / self.subharmonic

    @property
    def period(self) -> float:
        """Orbit period 2 pi subharmonic / omega, s."""
        return 2.0 * np.pi / self.base_frequency

    @property
    def mean(self) -> np.ndarray:
        """Mean value per coordinate, (n,)."""
        return self.harmonics[self.m].real.copy()

    @property
    def tail(self) -> float:
        """|q_{+-m}| relative to the largest harmonic: small when m is large enough."""
        return spectral_tail(self.harmonics)

    def _at(self, coefficients: np.ndarray, t) -> np.ndarray:
        return synthesize(coefficients, self.base_frequency * np.atleast_1d(np.asarray(t, dtype=float)))

    def __call__(self, t) -> np.ndarray:
        """q at times t (s): (len(t), n)."""
        return self._at(self.harmonics, t)

    def velocity(self, t) -> np.ndarray:
        """q' at times t (s): (len(t), n)."""
        l = np.arange(-self.m, self.m + 1)
        return self._at(self.harmonics * (1j * l * self.base_frequency)[:, None], t)

    def lam(self, t) -> np.ndarray:
        """Constraint forces (Lagrange multipliers) at times t (s): (len(t), n_c)."""
        if self.lambda_harmonics is None:
            return np.zeros((np.atleast_1d(t).size, 0))
        return self._at(self.lambda_harmonics, t)

    def amplitude(self) -> np.ndarray:
        """Half peak-to-peak of each coordinate over one period, (n,)."""
        return half_range_and_mean(self.harmonics)[0]

    # ------------------------------------------------------------------ outputs
    @property
    def _outputs(self) -> np.ndarray:
        return self.harmonics if self.output_spectrum is None else self.output_spectrum

    @property
    def output_harmonics(self) -> np.ndarray:
        """Output harmonics l = -m..m, (2m+1, n_out) complex."""
        M = (self._outputs.shape[0] - 1) // 2
        return self._outputs[M - self.m: M + self.m + 1]

    def outputs(self, t) -> np.ndarray:
        """Outputs y = G(t) q(t) at times t (s): (len(t), n_out)."""
        return self._at(self._outputs, t)

    def output_amplitude(self) -> np.ndarray:
        """Half peak-to-peak of each output over one period, (n_out,)."""
        return half_range_and_mean(self._outputs)[0]

    def output_mean(self) -> np.ndarray:
        """Mean of each output, (n_out,)."""
        M = (self._outputs.shape[0] - 1) // 2
        return self._outputs[M].real

    # ------------------------------------------------------------------ stability
    @property
    def multipliers(self) -> np.ndarray | None:
        """Floquet multipliers of the orbit (over its period), or None without stability."""
        return None if self.stability is None else self.stability.multipliers

    @property
    def max_multiplier(self) -> float:
        """Largest |mu| (nan without stability)."""
        mu = self.multipliers
        return float(np.max(np.abs(mu))) if mu is not None and len(mu) else float("nan")

    @property
    def stable(self) -> bool | None:
        """The stability verdict of ``stability`` (None when not computed)."""
        return None if self.stability is None else bool(self.stability.stable)
