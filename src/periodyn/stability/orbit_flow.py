"""Certified Magnus monodromy of a small orbit straight from its samples.

An orbit's perturbation ``y' = A(tau) y`` (y = (dq, dq'), tau = Om t over one orbit
period T = 2 pi / Om) is known at the p equidistant angles where harmonic balance
samples it. Its trigonometric interpolant (harmonics up to (p - 1) // 2, the ones the
samples resolve) is taken at the Gauss angles of N equal steps, and the 6th-order Magnus
integrator on the entries that vary along the orbit gives the monodromy matrix.
Step doubling N = START, 2 START, ... certifies it as the stability method "auto" does
(:class:`periodyn.stability.magnus.MagnusLadder`, whose error test this is: the change
of log max|mu| and of the sorted moduli between N / 2 and N steps, at least ERROR_FLOOR,
at most STABILITY_TOL max(1, |log max|mu||), and the verdict not within it), from the
ladder's first rung. No reduced system, no spectra, no ladder set-up, no balancing: the
registry's rule (:func:`periodyn.stability.methods.flow_choice`) sends stiff orbits to the
ladder. The whole climb is one compiled call
(:func:`periodyn.kernels.solvers.sampled_flow.certified_flow`): for a one-degree-of-freedom
orbit, a few 2 x 2 products per step and microseconds per orbit; a chain's sparse step
generators multiply by their nonzero entries, and the multipliers of mid-size orbits come
from LAPACK's double-shift QR (:mod:`periodyn.kernels.solvers.real_eigvals`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..kernels.solvers.sampled_flow import certified_flow, generator_stiffness
from .floquet import STABILITY_TOL, FloquetExponents
from .magnus import ERROR_FLOOR, MagnusLadder

__all__ = ["SampledGenerator", "varying_entries", "flow_exponents", "START", "LARGEST"]

START, LARGEST = MagnusLadder.START[6], 1024  # steps of the first compared rung (against START / 2), most steps


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

    @classmethod
    def from_blocks(cls, K: np.ndarray, C: np.ndarray) -> "SampledGenerator":
        """The generator [[0, I], [K_j, C_j]] (2n, 2n) from its lower blocks K, C (p, n, n) at
        the samples, without forming the full samples; a block given as a broadcast view
        (stride 0 along the samples) is constant."""
        p, n = K.shape[0], K.shape[1]
        constant = np.eye(2 * n, k=n)
        constant[n:, :n], constant[n:, n:] = K[0], C[0]
        at, values = [np.zeros(0, np.intp)], [np.zeros((p, 0))]
        for first, B in ((0, K), (n, C)):
            if B.strides[0] != 0:
                flat = B.reshape(p, -1)
                v = varying_entries(flat)
                at.append(2 * n * n + (v // n) * (2 * n) + first + v % n)  # flat index in (2n, 2n)
                values.append(flat[:, v])
        at = np.concatenate(at)
        order = np.argsort(at)
        return cls(constant, at[order], np.concatenate(values, axis=1)[:, order])

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
        return generator_stiffness(self.constant, self.varying, self.values) * 2 * np.pi * subharmonic / float(omega)


def flow_exponents(A, omega: float, subharmonic: int = 1, reason: str = "") -> FloquetExponents | None:
    """Exponents (d, rad/s) of ``y' = A(t) y`` from its samples A (p, d, d) (1/s, or a
    :class:`SampledGenerator`) at
    t_j = T j / p over the orbit period T = 2 pi subharmonic / omega (omega: driving speed,
    rad/s), certified by step doubling (module docstring); None when LARGEST steps do not
    certify them (or the monodromy is not finite). Samples that repeat after half a period
    (p even, to 1e-12 of their largest entry) are integrated over that half only (the
    monodromy is Phi(T/2)^2). reason: why this method (kept, followed by the steps and the
    error estimate, on the result)."""
    period = 2 * np.pi * subharmonic / float(omega)
    gen = A if isinstance(A, SampledGenerator) else SampledGenerator.from_samples(A)
    lam = np.empty(gen.constant.shape[0], complex)
    steps, err, half = certified_flow(gen.constant, gen.varying, gen.values, period, START, LARGEST, STABILITY_TOL,
                                      ERROR_FLOOR, lam)
    if not steps:
        return None
    nan = np.full(lam.size, np.nan)
    how = (f"Magnus of order 6 on the orbit's samples with {steps} steps"
           f"{' per half period' if half else ''}: estimated error {err:.1g} (tolerance {STABILITY_TOL:g})")
    return FloquetExponents(float(omega), lam, nan, nan.copy(), "magnus",
                            int(subharmonic), reason=f"{reason}; {how}" if reason else how)
