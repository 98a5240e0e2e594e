"""Harmonic balance for rheo-linear systems (Schwab & Meijaard eq. 14-18).

With ``q(t) = sum_{l=-m..m} q_l exp(i l w t)`` and coefficient spectra ``X_k``, balancing
harmonic ``k`` gives the block system (direct Galerkin form on M, C, K)

    sum_l [K_{k-l} + i l w C_{k-l} - (l w)^2 M_{k-l}] q_l = f_k,      k = -m..m,

and the paper's form (16)-(18) is the same with M -> I, C -> P = M^-1 C, K -> Q = M^-1 K,
f -> r = M^-1 f per sample. The matrix is block-banded with the bandwidth of the
coefficient spectra; it is made by :class:`periodyn.harmonic.HarmonicOperator` and
factorized dense (real form), banded or sparse, whichever :func:`balance_storage`
estimates cheapest.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from .errors import ConvergenceError, InputError
from .harmonic.operator import BAND_RTOL as _BAND_RTOL
from .harmonic.operator import FORMS, AliasingWarning, HarmonicOperator, HillOperator, check_harmonics
from .harmonic.pattern import BlockPattern, from_real_basis, real_form, to_real_basis
from .kernels.harmonic import half_range as _half_range_kernel
from .spectra import spectral_tail, synthesize, to_samples
from .system import RheoLinear

__all__ = ["PeriodicSolution", "periodic_solution", "AliasingWarning", "FORMS", "BalanceStorage", "balance_storage",
           "solve_balance", "check_harmonics"]


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


@dataclass(frozen=True, eq=False)
class PeriodicSolution:
    """Periodic solution ``q(t) = sum_l harmonics[l+m] exp(i l omega t)`` of a rheo-linear system.

    omega: rad/s; harmonics: (2m+1, n) complex, l = -m..m; output_spectrum:
    (2M+1, n_out) complex spectrum of the outputs y = G(t) q(t) (M = m + band of G);
    residual: ||H x - f|| / ||f|| of the balance equations; form: "direct"|"inverse-mass".
    """

    omega: float
    harmonics: np.ndarray
    output_spectrum: np.ndarray
    coordinate_names: tuple[str, ...]
    output_names: tuple[str, ...]
    residual: float
    form: str

    @property
    def m(self) -> int:
        return (self.harmonics.shape[0] - 1) // 2

    @property
    def mean(self) -> np.ndarray:
        """Mean value per coordinate, (n,)."""
        return self.harmonics[self.m].real

    @property
    def output_harmonics(self) -> np.ndarray:
        """Output harmonics l = -m..m, (2m+1, n_out) complex."""
        M = (self.output_spectrum.shape[0] - 1) // 2
        return self.output_spectrum[M - self.m: M + self.m + 1]

    @property
    def tail(self) -> float:
        """|q_{+-m}| relative to the largest harmonic: small when m is large enough."""
        return spectral_tail(self.harmonics)

    def __call__(self, t) -> np.ndarray:
        """q at times t (s): (len(t), n)."""
        return synthesize(self.harmonics, self.omega * np.atleast_1d(np.asarray(t, dtype=float)))

    def velocity(self, t) -> np.ndarray:
        """q' at times t (s): (len(t), n)."""
        l = np.arange(-self.m, self.m + 1)
        return synthesize(self.harmonics * (1j * l * self.omega)[:, None], self.omega * np.atleast_1d(t))

    def outputs(self, t) -> np.ndarray:
        """Outputs y = G(t) q(t) at times t (s): (len(t), n_out)."""
        return synthesize(self.output_spectrum, self.omega * np.atleast_1d(np.asarray(t, dtype=float)))

    def amplitude(self) -> np.ndarray:
        """Half peak-to-peak of each coordinate over one period, (n,)."""
        return half_range_and_mean(self.harmonics)[0]

    def output_amplitude(self) -> np.ndarray:
        """Half peak-to-peak of each output over one period, (n_out,)."""
        return half_range_and_mean(self.output_spectrum)[0]

    def output_mean(self) -> np.ndarray:
        """Mean of each output, (n_out,)."""
        M = (self.output_spectrum.shape[0] - 1) // 2
        return self.output_spectrum[M].real


def output_spectrum(G: np.ndarray, harmonics: np.ndarray) -> np.ndarray:
    """Spectrum of y = G(t) q(t): G (2KG+1, n_out, n), q (..., 2m+1, n) ->
    (..., 2(m+KG')+1, n_out), with KG' the significant band of G (the product is exact,
    no aliasing); leading axes (e.g. speeds) are carried along."""
    KG = (G.shape[0] - 1) // 2
    mag = np.abs(G).reshape(G.shape[0], -1).max(axis=1)
    big = np.nonzero(mag > _BAND_RTOL * max(mag.max(), np.finfo(float).tiny))[0]
    kg = int(np.abs(big - KG).max()) if big.size else 0
    G = G[KG - kg: KG + kg + 1]
    m = (harmonics.shape[-2] - 1) // 2
    out = np.zeros(harmonics.shape[:-2] + (2 * (m + kg) + 1, G.shape[1]), dtype=complex)
    for j in range(2 * kg + 1):  # y_{l + (j-kg)} += G_{j-kg} q_l
        out[..., j: j + 2 * m + 1, :] += harmonics @ G[j].T
    return out


def singular_balance(omega: float, detail: str) -> InputError:
    """The error for an exactly singular HB matrix at omega (rad/s)."""
    return InputError(f"the harmonic balance matrix is singular at omega = {omega:.6g} rad/s (an undamped "
                      f"resonance: a characteristic exponent is a multiple of i*omega); add damping or move omega "
                      f"({detail})")


RESIDUAL_MAX = 1e-6  # relative HB residual above which an LU solve failed (backward-stable: ~1e-15)
_WORK_BYTES = 4e8  # working memory allowed for one HB factorization (dense or band storage)


@dataclass(frozen=True)
class BalanceStorage:
    """How the HB matrix is stored and factorized: kind "dense" (real form, LAPACK
    getrf), "banded" (complex, LAPACK gbtrf) or "sparse" (SuperLU); reason: the cost
    estimate behind the choice."""

    kind: str
    reason: str


def balance_storage(pattern: BlockPattern) -> BalanceStorage:
    """The cheaper factorization of the (N, N) HB matrix with half-bandwidth u: dense real
    LU costs about N^3/3 multiply-adds, banded complex LU about 2 N u^2 (one complex
    multiply-add is ~4 real ones, and the band LU does ~N u^2 / 2 of them; measured: the
    two break even near u = 0.4 N). Sparse LU only when neither fits in memory (the
    pattern's blocks are full, so SuperLU gains no sparsity over the band)."""
    return _storage(pattern.size, pattern.half_bandwidth)


@lru_cache(maxsize=256)
def _storage(N: int, u: int) -> BalanceStorage:
    dense, banded = N**3 / 3.0, 2.0 * N * u**2
    dense_bytes, band_bytes = 48.0 * N**2, 16.0 * N * (3 * u + 1)
    sizes = f"N = {N}, u = {u}: dense N^3/3 = {dense:.3g}, banded 2 N u^2 = {banded:.3g}"
    if banded <= dense and band_bytes <= _WORK_BYTES:
        return BalanceStorage("banded", f"banded cheaper ({sizes})")
    if dense_bytes <= _WORK_BYTES:
        return BalanceStorage("dense", f"dense real cheaper ({sizes})")
    if band_bytes <= _WORK_BYTES:
        return BalanceStorage("banded", f"banded, dense needs {dense_bytes:.3g} B ({sizes})")
    return BalanceStorage("sparse", f"sparse LU, dense and band storage exceed {_WORK_BYTES:.0e} B ({sizes})")


def solve_balance(op: HillOperator, storage: BalanceStorage | None = None) -> tuple[np.ndarray, float]:
    """Solve W x = rhs with the storage of :func:`balance_storage` (or the one given).
    Returns harmonics (2m+1, n) and the relative residual; a non-finite solution raises
    ConvergenceError, an exactly singular matrix InputError."""
    pat, W, m, n = op.pattern, op.blocks[0], op.m, op.n
    kind = (storage or balance_storage(pat)).kind
    try:
        if kind == "banded":
            u = pat.half_bandwidth
            x = sla.solve_banded((u, u), pat.banded(W), op.rhs, overwrite_ab=True, check_finite=False)
        elif kind == "dense":
            y = np.linalg.solve(real_form(pat.dense(W), m, n, halves=1), to_real_basis(op.rhs, m, n, halves=1))
            x = from_real_basis(y[:, None], m, n, halves=1)[:, 0]
        else:
            x = spla.splu(op.W).solve(op.rhs)
    except (RuntimeError, np.linalg.LinAlgError) as exc:  # exactly singular: undamped resonance
        raise singular_balance(op.omega, str(exc)) from None
    scale = np.linalg.norm(op.rhs)
    residual = float(np.linalg.norm(pat.apply(W, x) - op.rhs))
    residual = residual / scale if scale > 0 else residual
    if not residual <= RESIDUAL_MAX:  # also NaN
        raise ConvergenceError(f"the harmonic balance solve ({kind}) at omega = {op.omega:.6g} rad/s gave a "
                               f"non-finite or inaccurate solution (relative residual {residual:.3g}); the HB matrix "
                               "is numerically singular or overflows (add damping, move omega or rescale the model)",
                               residual=residual, iterations=1)
    q = x.reshape(2 * m + 1, n)
    q = 0.5 * (q + np.conj(q[::-1]))  # enforce the conjugate symmetry of a real solution
    return q, residual


def periodic_solution(system: RheoLinear, harmonics: int, *, form: str = "direct",
                      operator: HillOperator | None = None) -> PeriodicSolution:
    """Periodic solution by harmonic balance (eq. 18) with ``harmonics`` = m >= 1 harmonics.

    form="direct" balances M, C, K (Galerkin on the original form, keeps symmetry);
    form="inverse-mass" balances the paper's P = M^-1 C, Q = M^-1 K, r = M^-1 f (eq. 16).
    operator: the :class:`HillOperator` of this system, form and m at system.omega, when
    already built (e.g. ``HarmonicOperator.for_system(system, m, form).at(system.omega)``).
    """
    m = check_harmonics(harmonics)
    if operator is None:
        operator = HarmonicOperator.for_system(system, m, form).at(system.omega)
    q, residual = solve_balance(operator)
    return PeriodicSolution(system.omega, q, output_spectrum(system.spectra.outputs, q), system.coordinate_names,
                            system.output_names, residual, form)
