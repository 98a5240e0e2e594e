"""Floquet results and the one stability verdict of periodyn.

A periodic linear system ``y' = A(t) y`` of period T has characteristic multipliers
``mu`` (eigenvalues of the monodromy matrix) and exponents ``lambda`` with
``mu = exp(lambda T)``; ``|mu| = exp(Re(lambda) T)``. Linear (Hill, monodromy, Magnus)
and non-linear (shooting, IHB) results all state stability by :func:`is_stable`:

    stable  <=>  max Re(lambda) T = log max |mu| <= STABILITY_TOL.

The rule is written on the growth per period, ``log |mu|``, so that it does not depend
on the speed or on the (subharmonic) period, and is the same whether exponents or
multipliers were computed. The tolerance 1e-6 is above what the methods resolve near a
neutral multiplier (Hill exponents and Magnus/DOP853 multipliers agree to about 1e-8 per
period), so a conservative (undamped) orbit, whose multipliers lie on the unit circle, is
called stable instead of stable or unstable by the sign of round-off; a genuine
instability grows by more than 1e-6 per period. For the DAE path it is the former
``|mu| <= 1 + 1e-6`` (log(1 + 1e-6) = 1e-6 - 5e-13); for the linear path it replaces
``max Re(lambda) < 0``, which differs only for growth below 1e-6 per period.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FloquetExponents", "STABILITY_TOL", "TRUNCATION_TOL", "TruncationWarning", "is_stable",
           "truncation_message"]

STABILITY_TOL = 1e-6  # largest admissible growth per period, log max|mu| = max Re(lambda) T
#: Largest admissible fraction of a Hill eigenvector's energy in the outermost harmonics |l| = m.
#: On 1,200 elliptic-pendulum cases (m = 1-6, dense Hill against DOP853 monodromy) every wrong
#: verdict had an edge fraction above 4e-6, and below 1e-6 log max|mu| was within 1.3e-7 of the
#: reference (below STABILITY_TOL).
TRUNCATION_TOL = 1e-6


class TruncationWarning(UserWarning):
    """A Hill verdict whose truncation indicator (edge energy) is above TRUNCATION_TOL."""


def truncation_message(edge: float, harmonics: int, omega: float, method: str) -> str:
    """Why a Hill result with edge energy fraction ``edge`` at m = ``harmonics`` is not trusted."""
    return (f"Hill's method ({method}) with harmonics = {harmonics} is truncated at omega = {omega:.6g} rad/s: "
            f"{edge:.2g} of an exponent's eigenvector energy is in the outermost harmonics (tolerance "
            f"{TRUNCATION_TOL:g}), so its verdict is not reliable; increase harmonics (e.g. to {2 * harmonics})")


def is_stable(max_real, period):
    """The one stability verdict: max Re(lambda) (1/s) times the period (s) at most
    :data:`STABILITY_TOL`. Works elementwise on arrays; NaN (a failed analysis) is False."""
    return np.asarray(max_real) * np.asarray(period) <= STABILITY_TOL


@dataclass(frozen=True, eq=False)
class FloquetExponents:
    """Characteristic exponents of a periodic linear system of 2n first-order equations.

    omega: driving speed, rad/s; subharmonic: the response period is
    ``period = 2 pi subharmonic / omega`` (s). exponents: (2n,) complex, rad/s -- for
    Hill's method the eigenvector-centred representative (its imaginary part is the
    physical vibration frequency), from a monodromy matrix the principal value.
    multipliers = exp(lambda period). centroid: (2n,) harmonic-energy centroid of the
    chosen Hill eigenvectors; edge: (2n,) fraction of their energy in the outermost
    harmonics |l| = m, the truncation indicator (raise m when it is not small); both NaN
    without Hill. method: how they were computed; reason: why (when chosen by "auto").
    """

    omega: float
    exponents: np.ndarray
    centroid: np.ndarray
    edge: np.ndarray
    method: str
    subharmonic: int = 1
    reason: str = ""

    @classmethod
    def from_multipliers(cls, multipliers, omega: float, method: str, subharmonic: int = 1) -> FloquetExponents:
        """Exponents log(mu) / period (principal logarithm) of multipliers (2n,)."""
        mu = np.asarray(multipliers, dtype=complex).reshape(-1)
        period = 2 * np.pi * subharmonic / float(omega)
        with np.errstate(divide="ignore"):
            lam = np.log(mu) / period
        nan = np.full(mu.size, np.nan)
        return cls(float(omega), lam, nan, nan.copy(), method, int(subharmonic))

    @property
    def truncation(self) -> float:
        """Hill's truncation indicator: the largest edge energy fraction (NaN without Hill);
        above :data:`TRUNCATION_TOL` the verdict is not reliable (raise the harmonics)."""
        edge = self.edge[np.isfinite(self.edge)]
        return float(edge.max()) if edge.size else float("nan")

    @property
    def period(self) -> float:
        """Period of the response, 2 pi subharmonic / omega (s)."""
        return 2 * np.pi * self.subharmonic / self.omega

    @property
    def multipliers(self) -> np.ndarray:
        """Characteristic multipliers exp(lambda period), (2n,) complex."""
        return np.exp(self.exponents * self.period)

    @property
    def principal(self) -> np.ndarray:
        """Exponents shifted by multiples of 2 pi i / period into |Im| <= pi / period, (2n,)."""
        step = 2 * np.pi / self.period
        return self.exponents - 1j * step * np.round(self.exponents.imag / step)

    @property
    def max_real(self) -> float:
        """Largest real part of the exponents (1/s); NaN without exponents."""
        return float(self.exponents.real.max()) if self.exponents.size else float("nan")

    @property
    def max_multiplier(self) -> float:
        """Largest multiplier modulus max |mu| = exp(max_real period)."""
        return float(np.abs(self.multipliers).max()) if self.exponents.size else float("nan")

    @property
    def stable(self) -> bool:
        """The verdict of :func:`is_stable` (no exponents: a system without dynamics, stable)."""
        return bool(self.exponents.size == 0 or is_stable(self.max_real, self.period))
