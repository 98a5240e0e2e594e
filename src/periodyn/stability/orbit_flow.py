"""Certified Magnus monodromy of a small orbit straight from its samples.

An orbit's perturbation ``y' = A(tau) y`` (y = (dq, dq'), tau = Om t over one orbit
period T = 2 pi / Om) is known at the p equidistant angles where harmonic balance
samples it. Its trigonometric interpolant (harmonics up to (p - 1) // 2, the ones the
samples resolve) is taken at the Gauss angles of N equal steps through a fixed (3N, p)
matrix, and the 6th-order Magnus kernel
(:func:`periodyn.kernels.solvers.floquet.sampled_magnus6`, on the entries that vary along the orbit)
gives the monodromy matrix.
Step doubling N = START, 2 START, ... certifies it as the stability method "auto" does
(:class:`periodyn.stability.magnus.MagnusLadder`, whose error test this is: the change
of log max|mu| and of the sorted moduli between N / 2 and N steps, at least ERROR_FLOOR,
at most STABILITY_TOL max(1, |log max|mu||), and the verdict not within it), from the
ladder's first rung. No reduced system, no spectra, no ladder set-up, no balancing: the
registry's rule (:func:`periodyn.stability.methods.flow_choice`) sends stiff orbits to the
ladder. For a one-degree-of-freedom orbit the analysis is a few 2 x 2 products per step.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.linalg as sla

from ..kernels.solvers.floquet import sampled_magnus6
from .floquet import STABILITY_TOL, FloquetExponents
from .magnus import ERROR_FLOOR, MagnusLadder, gauss_angles

__all__ = ["SampledGenerator", "varying_entries", "flow_exponents", "interpolation_matrix", "START", "LARGEST"]

START, LARGEST = MagnusLadder.START[6], 1024  # steps of the first compared rung (against START / 2), most steps


@lru_cache(maxsize=32)
def interpolation_matrix(p: int, steps: int) -> np.ndarray:
    """(3 steps, p): values at the order-6 Gauss angles of ``steps`` steps over 2 pi of the
    trigonometric interpolant (harmonics 0..(p-1)//2) of p samples at 2 pi j / p."""
    theta = gauss_angles(steps, points=3)
    diff = theta[:, None] - 2 * np.pi * np.arange(p)[None, :] / p
    k = np.arange(1, (p - 1) // 2 + 1)
    return (1.0 + 2.0 * np.cos(diff[:, :, None] * k).sum(axis=2)) / p


def varying_entries(flat: np.ndarray) -> np.ndarray:
    """Indices (v,) of the columns of samples flat (p, N) that differ from the first row."""
    return np.nonzero((flat != flat[0]).any(axis=0))[0]


@dataclass(frozen=True)
class SampledGenerator:
    """Samples A_j (p, d, d) (1/s) of the generator of ``y' = A(t) y`` at p equidistant
    times over one period, kept as the first sample and the entries that vary: A_j equals
    ``constant`` (d, d) with its flat entries ``varying`` (v,) replaced by ``values[j]``
    (p, v). An orbit's perturbation changes few entries along it (a cubic chain's 80 x 80
    generator: 40 of 6,400), and every step below works on those alone."""

    constant: np.ndarray
    varying: np.ndarray
    values: np.ndarray

    @classmethod
    def from_samples(cls, A: np.ndarray) -> "SampledGenerator":
        """From full samples A (p, d, d)."""
        A = np.asarray(A, dtype=float)
        flat = A.reshape(A.shape[0], -1)
        varying = varying_entries(flat)
        return cls(A[0].copy(), varying, flat[:, varying])

    @property
    def samples(self) -> np.ndarray:
        """The full samples A (p, d, d)."""
        d = self.constant.shape[0]
        flat = np.repeat(self.constant.reshape(1, -1), self.values.shape[0], axis=0)
        flat[:, self.varying] = self.values
        return flat.reshape(-1, d, d)

    def stiffness(self, omega: float, subharmonic: int = 1) -> float:
        """max_j ||A_j||_1 T: the size of the generator over one orbit period T = 2 pi
        subharmonic / omega (Magnus needs steps in proportion to it; the ladder of "auto"
        balances stiff systems first)."""
        d = self.constant.shape[0]
        sums = np.repeat(np.abs(self.constant).sum(axis=0)[None], self.values.shape[0], axis=0)  # (p, d)
        if self.varying.size:  # each sample's column sums: the first's, changed in the varying entries' columns
            change = np.abs(self.values) - np.abs(self.constant.ravel()[self.varying])  # (p, v)
            order = np.argsort(self.varying % d, kind="stable")
            columns, starts = np.unique(self.varying[order] % d, return_index=True)
            sums[:, columns] += np.add.reduceat(change[:, order], starts, axis=1)
        return float(sums.max()) * 2 * np.pi * subharmonic / float(omega)

    def half_period(self) -> bool:
        """Whether the samples repeat after half the period (p even, to 1e-12 of their
        largest entry): then the monodromy is Phi(T/2)^2."""
        p, V = self.values.shape[0], self.values
        if p % 2:
            return False
        largest = max(float(np.abs(self.constant).max(initial=0.0)), float(np.abs(V).max(initial=0.0)))
        return bool(np.abs(V[p // 2:] - V[:p // 2]).max(initial=0.0) <= 1e-12 * largest)

    def first_half(self) -> "SampledGenerator":
        """The samples of the first half period (p even), with the entries varying there."""
        V = self.values[: self.values.shape[0] // 2]
        keep = varying_entries(V)
        return SampledGenerator(self.constant, self.varying[keep], V[:, keep])

    def monodromy(self, steps: int, period: float) -> np.ndarray:
        """Transition matrix (d, d) over ``period`` (s), the span of the samples, with
        ``steps`` order-6 Magnus steps of their trigonometric interpolant (the constant
        entries interpolate to their value)."""
        phi = np.empty(self.constant.shape)
        sampled_magnus6(self.constant, self.varying, self.values, interpolation_matrix(self.values.shape[0], steps),
                        period / steps, phi)
        return phi


def _generator(A) -> SampledGenerator:
    return A if isinstance(A, SampledGenerator) else SampledGenerator.from_samples(A)


def _eigvals(phi: np.ndarray) -> np.ndarray:
    """Eigenvalues of a real square matrix; 2 x 2 in closed form (the larger root first,
    the other from the determinant: no cancellation)."""
    if phi.shape[0] != 2:
        return sla.eigvals(phi, overwrite_a=True, check_finite=False)
    (a, b), (c, e) = phi.tolist()
    half, det = 0.5 * (a + e), a * e - b * c
    root = cmath.sqrt(half * half - det)
    big = half + root if half >= 0 else half - root
    return np.array([big, det / big if big != 0 else 0.0], dtype=complex)


def flow_exponents(A, omega: float, subharmonic: int = 1, reason: str = "") -> FloquetExponents | None:
    """Exponents (d, rad/s) of ``y' = A(t) y`` from its samples A (p, d, d) (1/s, or a
    :class:`SampledGenerator`) at
    t_j = T j / p over the orbit period T = 2 pi subharmonic / omega (omega: driving speed,
    rad/s), certified by step doubling (module docstring); None when LARGEST steps do not
    certify them (or the monodromy is not finite). Samples that repeat after half a period
    (:meth:`SampledGenerator.half_period`) are integrated over that half only. reason: why this method (kept,
    followed by the steps and the error estimate, on the result)."""
    period = 2 * np.pi * subharmonic / float(omega)
    gen = _generator(A)
    half = gen.half_period()
    span = gen.first_half() if half else gen
    G0 = mod0 = None
    steps = START // 2
    while steps <= LARGEST:
        phi = span.monodromy(steps, period / 2 if half else period)
        if not math.isfinite(phi.sum()):
            return None
        mu = _eigvals(phi) ** 2 if half else _eigvals(phi)  # eig(Phi(T/2)^2) = eig(Phi(T/2))^2
        mod = np.sort(np.abs(mu))
        if not mod[-1] > 0:
            return None
        G = math.log(mod[-1])
        if G0 is not None:
            err = max(abs(G - G0), float(np.abs(mod - mod0).max()) / mod[-1], ERROR_FLOOR)
            if err <= STABILITY_TOL * max(1.0, abs(G)) and abs(G - STABILITY_TOL) > err:
                lam = np.log(mu.astype(complex)) / period  # principal values
                nan = np.full(lam.size, np.nan)
                how = (f"Magnus of order 6 on the orbit's samples with {steps} steps"
                       f"{' per half period' if half else ''}: estimated error {err:.1g} (tolerance {STABILITY_TOL:g})")
                return FloquetExponents(float(omega), lam[np.lexsort((lam.imag, lam.real))], nan, nan.copy(), "magnus",
                                        int(subharmonic), reason=f"{reason}; {how}" if reason else how)
        G0, mod0 = G, mod
        steps *= 2
    return None
