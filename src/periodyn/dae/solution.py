"""Periodic solution of a DAE/ODE (from IHB or shooting): one frozen result object."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from ..spectra import synthesize

__all__ = ["PeriodicSolution"]

STABILITY_TOL = 1e-6  # |mu| <= 1 + tol counts as stable (multipliers accurate to ~1e-8)


@dataclass(frozen=True, eq=False)
class PeriodicSolution:
    """Periodic orbit ``q(t) = sum_k c_k exp(i k Omega t)``, ``Omega = omega / subharmonic``.

    omega: driving frequency (rad/s); subharmonic: nu (1: period T = 2 pi/omega,
    2: period-doubled orbit of period 2T). harmonics: (2H+1, n) complex two-sided
    (index k + H) of q; lambda_harmonics: (2H+1, m) of the Lagrange multipliers (N or N m).
    residual: final residual norm (max-norm, SI units of the equations); iterations: Newton
    steps. multipliers: (2(n-m),) complex Floquet multipliers of the independent-coordinate
    perturbation equations, or None when stability was not computed.
    """

    omega: float
    subharmonic: int
    harmonics: np.ndarray
    lambda_harmonics: np.ndarray
    residual: float
    iterations: int
    multipliers: np.ndarray | None
    method: str
    parameters: Mapping[str, float]
    coordinate_names: tuple[str, ...]
    constraint_names: tuple[str, ...]
    samples: int

    @property
    def period(self) -> float:
        """Orbit period nu 2 pi / omega, s."""
        return 2.0 * np.pi * self.subharmonic / self.omega

    @property
    def base_frequency(self) -> float:
        """Omega = omega / nu, rad/s."""
        return self.omega / self.subharmonic

    @property
    def mean(self) -> np.ndarray:
        """Mean of q over a period, (n,)."""
        H = (self.harmonics.shape[0] - 1) // 2
        return self.harmonics[H].real.copy()

    def __call__(self, t) -> np.ndarray:
        """q at times t (s): (len(t), n)."""
        return synthesize(self.harmonics, self.base_frequency * np.atleast_1d(np.asarray(t, float)))

    def velocity(self, t) -> np.ndarray:
        """q' at times t: (len(t), n), units of q per s."""
        H = (self.harmonics.shape[0] - 1) // 2
        d = 1j * self.base_frequency * np.arange(-H, H + 1)
        return synthesize(self.harmonics * d[:, None], self.base_frequency * np.atleast_1d(np.asarray(t, float)))

    def lam(self, t) -> np.ndarray:
        """Lagrange multipliers at times t: (len(t), m)."""
        return synthesize(self.lambda_harmonics, self.base_frequency * np.atleast_1d(np.asarray(t, float)))

    def amplitude(self, samples: int = 512) -> np.ndarray:
        """Half peak-to-peak of each coordinate over one period, (n,)."""
        q = self(np.arange(samples) * self.period / samples)
        return 0.5 * (q.max(axis=0) - q.min(axis=0))

    @property
    def max_multiplier(self) -> float:
        """Largest |mu| (nan without stability)."""
        return float(np.max(np.abs(self.multipliers))) if self.multipliers is not None and len(self.multipliers) else float("nan")

    @property
    def stable(self) -> bool | None:
        """All |mu| <= 1 + 1e-6; None when multipliers were not computed."""
        if self.multipliers is None:
            return None
        return bool(len(self.multipliers) == 0 or self.max_multiplier <= 1.0 + STABILITY_TOL)
