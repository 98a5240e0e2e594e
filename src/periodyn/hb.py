"""Harmonic balance for rheo-linear systems (Schwab & Meijaard eq. 14-18).

With ``q(t) = sum_{l=-m..m} q_l exp(i l w t)`` and coefficient spectra ``X_k``, balancing
harmonic ``k`` gives the block system (direct Galerkin form on M, C, K)

    sum_l [K_{k-l} + i l w C_{k-l} - (l w)^2 M_{k-l}] q_l = f_k,      k = -m..m,

and the paper's form (16)-(18) is the same with M -> I, C -> P = M^-1 C, K -> Q = M^-1 K,
f -> r = M^-1 f per sample. The matrix is block-banded with the bandwidth of the
coefficient spectra; it is assembled sparsely on a cached pattern and solved by sparse LU.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .errors import InputError
from .periodic import PeriodicSolution, half_range_and_mean, output_spectrum  # noqa: F401 (re-exported)
from .spectra import spectral_tail
from .system import RheoLinear, Spectra

__all__ = ["PeriodicSolution", "periodic_solution", "AliasingWarning", "FORMS"]

FORMS = ("direct", "inverse-mass")
_BAND_RTOL = 1e-13  # coefficient harmonics below this fraction of the largest are dropped
_TAIL_WARN = 1e-6  # spectral tail above which the coefficient sampling is called too coarse
_NOISE = 1e-14  # coefficients below this fraction of the largest one are round-off


class AliasingWarning(UserWarning):
    """The coefficient spectra are not resolved by the sample count (aliasing)."""


def check_harmonics(harmonics) -> int:
    if isinstance(harmonics, bool) or not isinstance(harmonics, (int, np.integer)) or harmonics < 0:
        raise InputError(f"harmonics must be a non-negative integer number of harmonics m, got {harmonics!r}")
    return int(harmonics)


def check_form(form: str) -> str:
    if form not in FORMS:
        raise InputError(f"unknown form {form!r}; choose one of {FORMS}")
    return form


def check_sampling(p: int, m: int, *coefficient_spectra: np.ndarray) -> None:
    """Refuse p < 2m+1 samples; warn (AliasingWarning) when the top quarter of any
    coefficient spectrum is above 1e-6 of its largest harmonic (coefficients at round-off
    level, below 1e-14 of the largest entry of all spectra, are not checked)."""
    if p < 2 * m + 1:
        raise InputError(f"{p} samples per period cannot resolve {m} harmonics; use samples >= {2 * m + 1} "
                         f"(>= {4 * m + 1} to keep all coefficient couplings)")
    scale = max(float(np.abs(X).max(initial=0.0)) for X in coefficient_spectra)
    # a coefficient that is round-off next to the others (e.g. the omega-term of an
    # undamped model's damping) has no spectrum worth checking
    tail = max((spectral_tail(X) for X in coefficient_spectra if np.abs(X).max(initial=0.0) > _NOISE * scale),
               default=0.0)
    if tail > _TAIL_WARN:
        warnings.warn(f"coefficient spectra are not resolved by {p} samples (spectral tail {tail:.1e}); "
                      "increase samples to avoid aliasing", AliasingWarning, stacklevel=4)


def system_spectra(system: RheoLinear, harmonics: int, form: str) -> Spectra:
    """Coefficient spectra for the chosen form, after checking the sampling is adequate."""
    m = check_harmonics(harmonics)
    if not isinstance(system, RheoLinear):
        raise InputError(f"expected a periodyn.RheoLinear system, got {type(system).__name__}; "
                         "build one with RheoLinear.from_functions/from_samples or model.at(omega)")
    spectra = system.spectra if check_form(form) == "direct" else system.inverse_mass_spectra
    check_sampling(system.samples, m, spectra.mass, spectra.damping, spectra.stiffness)
    return spectra


def coefficient_band(spectra: Spectra, m: int) -> int:
    """Highest coefficient harmonic that couples the balance equations (<= 2m)."""
    K = (spectra.mass.shape[0] - 1) // 2
    band = 0
    for X in (spectra.mass, spectra.damping, spectra.stiffness):
        mag = np.abs(X).reshape(X.shape[0], -1).max(axis=1)
        big = np.nonzero(mag > _BAND_RTOL * max(mag.max(), np.finfo(float).tiny))[0]
        if big.size:
            band = max(band, int(np.abs(big - K).max()))
    return min(band, 2 * m)


@dataclass(frozen=True)
class BlockPattern:
    """Sparsity of a (2m+1)n block matrix with blocks (k, l) for |k - l| <= band.

    k_index, l_index: (nb,) harmonic indices of block rows/columns; csc_perm maps the
    flattened (nb, n, n) block data to CSC data order; indices/indptr are the CSC arrays;
    half_bandwidth u = (band + 1) n - 1 and band_rows/band_cols place the flattened block
    data in LAPACK band storage ab[u + i - j, j].
    """

    m: int
    n: int
    band: int
    k_index: np.ndarray
    l_index: np.ndarray
    csc_perm: np.ndarray
    indices: np.ndarray
    indptr: np.ndarray
    half_bandwidth: int
    band_rows: np.ndarray
    band_cols: np.ndarray

    @property
    def size(self) -> int:
        return (2 * self.m + 1) * self.n

    @property
    def narrow(self) -> bool:
        """Band storage pays off (LAPACK banded LU) over a general sparse LU."""
        return 4 * self.half_bandwidth < self.size

    def dense(self, blocks: np.ndarray) -> np.ndarray:
        """Dense (size, size) array of the block data (nb, n, n); for dense Hill only."""
        m, n = self.m, self.n
        out = np.zeros((2 * m + 1, n, 2 * m + 1, n), dtype=complex)
        out[self.k_index + m, :, self.l_index + m, :] = blocks
        return out.reshape(self.size, self.size)

    def banded(self, blocks: np.ndarray) -> np.ndarray:
        """LAPACK band storage (2u+1, size) of the block data (nb, n, n)."""
        ab = np.zeros((2 * self.half_bandwidth + 1, self.size), dtype=complex)
        ab[self.band_rows, self.band_cols] = blocks.reshape(-1)
        return ab

    def apply(self, blocks: np.ndarray, x: np.ndarray) -> np.ndarray:
        """Matrix-vector product of the block matrix with x (size,)."""
        m, n = self.m, self.n
        y = np.zeros((2 * m + 1, n), dtype=complex)
        np.add.at(y, self.k_index + m, np.einsum("bij,bj->bi", blocks, x.reshape(2 * m + 1, n)[self.l_index + m]))
        return y.reshape(-1)

    def matrix(self, blocks: np.ndarray) -> sp.csc_matrix:
        """CSC matrix from block data (nb, n, n)."""
        data = blocks.reshape(-1)[self.csc_perm]
        return sp.csc_matrix((data, self.indices, self.indptr), shape=(self.size, self.size))


@lru_cache(maxsize=64)
def block_pattern(m: int, n: int, band: int) -> BlockPattern:
    """The cached block pattern of (2m+1)n systems with coefficient band ``band``."""
    ks, ls = np.meshgrid(np.arange(-m, m + 1), np.arange(-m, m + 1), indexing="ij")
    keep = np.abs(ks - ls) <= band
    k_index, l_index = ks[keep], ls[keep]
    i_loc, j_loc = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    rows = ((k_index + m)[:, None, None] * n + i_loc[None]).reshape(-1)
    cols = ((l_index + m)[:, None, None] * n + j_loc[None]).reshape(-1)
    order = np.lexsort((rows, cols))
    size = (2 * m + 1) * n
    indptr = np.zeros(size + 1, dtype=np.int64)
    np.add.at(indptr, cols + 1, 1)
    indptr = np.cumsum(indptr)
    u = (band + 1) * n - 1
    return BlockPattern(m, n, band, k_index, l_index, order, rows[order].astype(np.int32),
                        indptr.astype(np.int32), u, u + rows - cols, cols)


def _take(X: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Coefficients X_d for offsets d (zero outside the stored range), (len(d), ...)."""
    K = (X.shape[0] - 1) // 2
    inside = np.abs(d) <= K
    out = np.zeros((d.size,) + X.shape[1:], dtype=complex)
    out[inside] = X[d[inside] + K]
    return out


def balance_blocks(spectra: Spectra, omega: float, pattern: BlockPattern):
    """Blocks of the quadratic Hill/HB operator at exponent 0 on ``pattern``.

    Returns (W, V, Mh), each (nb, n, n) complex, with
    W = K_{k-l} + i l w C_{k-l} - (l w)^2 M_{k-l}   (the HB matrix, eq. 18),
    V = C_{k-l} + 2 i l w M_{k-l}                 (eq. 27),
    Mh = M_{k-l}.
    """
    d = pattern.k_index - pattern.l_index
    Md, Cd, Kd = _take(spectra.mass, d), _take(spectra.damping, d), _take(spectra.stiffness, d)
    lw = (pattern.l_index * omega)[:, None, None]
    W = Kd + 1j * lw * Cd - lw**2 * Md
    V = Cd + 2j * lw * Md
    return W, V, Md


def force_vector(spectra: Spectra, m: int) -> np.ndarray:
    """Right-hand side f_k, k = -m..m, flattened ((2m+1) n,)."""
    return _take(spectra.force, np.arange(-m, m + 1)).reshape(-1)


@dataclass(frozen=True, eq=False)
class HillOperator:
    """The harmonic-balance / Hill operator of one system at one speed.

    Blocks on ``pattern`` (each (nb, n, n) complex): W (the HB matrix of eq. 18), V and
    Mh (eq. 27); ``.W``, ``.V``, ``.Mh`` give them as (2m+1)n square CSC matrices.
    rhs: ((2m+1)n,) force harmonics; identity_mass: Mh is the identity (inverse-mass form);
    real_first_order: optional precomputed real form of the first-order Hill matrix
    (2(2m+1)n square), as a speed sweep assembles it from polynomial terms in omega.
    """

    omega: float
    pattern: BlockPattern
    blocks: tuple[np.ndarray, np.ndarray, np.ndarray]
    rhs: np.ndarray
    identity_mass: bool
    real_first_order: np.ndarray | None = None

    @property
    def m(self) -> int:
        return self.pattern.m

    @property
    def n(self) -> int:
        return self.pattern.n

    @cached_property
    def W(self) -> sp.csc_matrix:
        return self.pattern.matrix(self.blocks[0])

    @cached_property
    def V(self) -> sp.csc_matrix:
        return self.pattern.matrix(self.blocks[1])

    @cached_property
    def Mh(self) -> sp.csc_matrix:
        return self.pattern.matrix(self.blocks[2])

    def dense(self, which: int) -> np.ndarray:
        """Block matrix 0 (W), 1 (V) or 2 (Mh) as a dense ((2m+1)n)^2 array (Hill only)."""
        return self.pattern.dense(self.blocks[which])


def hill_operator(spectra: Spectra, omega: float, m: int) -> HillOperator:
    """Blocks W, V, Mh on the cached block-banded pattern of the coefficient band."""
    n = spectra.mass.shape[1]
    pattern = block_pattern(m, n, coefficient_band(spectra, m))
    K = (spectra.mass.shape[0] - 1) // 2
    identity_mass = bool(np.array_equal(spectra.mass[K], np.eye(n)) and not np.any(np.delete(spectra.mass, K, axis=0)))
    return HillOperator(float(omega), pattern, balance_blocks(spectra, omega, pattern), force_vector(spectra, m),
                        identity_mass)


def singular_balance(omega: float, detail: str) -> InputError:
    """The error for an exactly singular HB matrix at omega (rad/s)."""
    return InputError(f"the harmonic balance matrix is singular at omega = {omega:.6g} rad/s (an undamped "
                      f"resonance: a characteristic exponent is a multiple of i*omega); add damping or move omega "
                      f"({detail})")


def solve_balance(op: HillOperator) -> tuple[np.ndarray, float]:
    """Solve W x = rhs: LAPACK banded LU for narrow bands, else sparse LU (no dense
    matrix either way). Returns harmonics (2m+1, n) and the relative residual."""
    pat, W = op.pattern, op.blocks[0]
    try:
        if pat.narrow:
            u = pat.half_bandwidth
            x = sla.solve_banded((u, u), pat.banded(W), op.rhs, overwrite_ab=True, check_finite=False)
        else:
            x = spla.splu(op.W).solve(op.rhs)
    except (RuntimeError, np.linalg.LinAlgError) as exc:  # exactly singular: undamped resonance
        raise singular_balance(op.omega, str(exc)) from None
    scale = np.linalg.norm(op.rhs)
    residual = np.linalg.norm(pat.apply(W, x) - op.rhs)
    q = x.reshape(2 * op.m + 1, op.n)
    q = 0.5 * (q + np.conj(q[::-1]))  # enforce the conjugate symmetry of a real solution
    return q, float(residual / scale if scale > 0 else residual)


def periodic_solution(system: RheoLinear, harmonics: int, *, form: str = "direct",
                      operator: HillOperator | None = None) -> PeriodicSolution:
    """Periodic solution by harmonic balance (eq. 18) with ``harmonics`` = m harmonics.

    form="direct" balances M, C, K (Galerkin on the original form, keeps symmetry);
    form="inverse-mass" balances the paper's P = M^-1 C, Q = M^-1 K, r = M^-1 f (eq. 16).
    operator: a prebuilt :class:`HillOperator` of this system, form and m (reused by sweeps).
    """
    m = check_harmonics(harmonics)
    if operator is None:
        operator = hill_operator(system_spectra(system, m, form), system.omega, m)
    q, residual = solve_balance(operator)
    return PeriodicSolution(system.omega, q, output_spectrum(system.spectra.outputs, q), system.coordinate_names,
                            system.output_names, residual, form)
