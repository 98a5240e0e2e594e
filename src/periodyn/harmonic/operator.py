"""The Hill / harmonic-balance operator of a periodic linear system, as polynomials in omega.

With ``q(t) = exp(lambda t) sum_l q_l exp(i l w t)`` and coefficient spectra X_k, the
equations ``M q'' + C q' + K q = f`` balance harmonic k as (Schwab & Meijaard eq. 18,
26-27; the paper's form has M -> I, C -> P = M^-1 C, K -> Q = M^-1 K, f -> M^-1 f)

    sum_l [lambda^2 Mh_kl + lambda V_kl + W_kl] q_l = f_k,
    W_kl = K_{k-l} + i l w C_{k-l} - (l w)^2 M_{k-l},  V_kl = C_{k-l} + 2 i l w M_{k-l},
    Mh_kl = M_{k-l}.

W is the HB matrix (lambda = 0). When ``C = sum_p w^p C_p``, ``K = sum_p w^p K_p`` and
``f = sum_p w^p f_p`` (a constant-speed :class:`OmegaSplitModel`; one term for a single
:class:`RheoLinear`), the blocks are polynomials ``W = sum_p w^p W_p`` (degree <= 4),
``V = sum_p w^p V_p``, Mh constant. :class:`HarmonicOperator` holds these terms, built
once, and evaluates them at one speed (:meth:`~HarmonicOperator.at`, a
:class:`HillOperator`) or at many (stacked banded / real dense HB matrices, real
first-order Hill matrices). Every HB and Hill matrix of periodyn is made here.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..errors import InputError
from ..numerics.spectra import BAND_RTOL, fourier_coefficients
from ..system import OmegaSplitModel, RheoLinear
from .pattern import BlockPattern, block_pattern, real_form, to_real_basis

__all__ = ["HarmonicOperator", "HillOperator", "AliasingWarning", "FORMS", "check_harmonics", "check_form",
           "first_order_matrix"]

FORMS = ("direct", "inverse-mass")
_TAIL_WARN = 1e-6  # spectral tail above which the coefficient sampling is called too coarse
_NOISE = 1e-14  # coefficients below this fraction of the largest one are round-off


class AliasingWarning(UserWarning):
    """The coefficient spectra are not resolved by the sample count (aliasing)."""


def check_harmonics(harmonics) -> int:
    """The harmonic count m, an integer >= 1 (m = 0 balances only the mean: no
    parametric coupling, so neither response nor stability would be right)."""
    if isinstance(harmonics, bool) or not isinstance(harmonics, (int, np.integer)) or harmonics < 1:
        raise InputError(f"harmonics must be an integer m >= 1 (the number of harmonics kept), got {harmonics!r}; "
                         "use at least the highest harmonic of the response, e.g. harmonics=8")
    return int(harmonics)


def check_form(form: str) -> str:
    if form not in FORMS:
        raise InputError(f"unknown form {form!r}; choose one of {FORMS}")
    return form


def check_sampling(p: int, m: int, *coefficient_spectra: np.ndarray) -> list[np.ndarray]:
    """Refuse p < 2m+1 samples; warn (AliasingWarning) when the top quarter of any
    coefficient spectrum is above 1e-6 of its largest harmonic (coefficients at round-off
    level, below 1e-14 of the largest entry of all spectra, are not checked). Returns the
    harmonic magnitudes of each spectrum (for :func:`coefficient_band`)."""
    if p < 2 * m + 1:
        raise InputError(f"{p} samples per period cannot resolve {m} harmonics; use samples >= {2 * m + 1} "
                         f"(>= {4 * m + 1} to keep all coefficient couplings)")
    mags = [_harmonic_magnitudes(X) for X in coefficient_spectra]
    scale = max(float(mag.max(initial=0.0)) for mag in mags)
    tail = max((_tail(mag) for mag in mags if mag.max(initial=0.0) > _NOISE * scale), default=0.0)
    if tail > _TAIL_WARN:
        warnings.warn(f"coefficient spectra are not resolved by {p} samples (spectral tail {tail:.1e}); "
                      "increase samples to avoid aliasing", AliasingWarning, stacklevel=5)
    return mags


def _harmonic_magnitudes(X: np.ndarray) -> np.ndarray:
    """Largest |entry| of each harmonic of a spectrum (2K+1, ...), (2K+1,)."""
    return np.abs(X).reshape(X.shape[0], -1).max(axis=1)


def _tail(mag: np.ndarray) -> float:
    """:func:`periodyn.numerics.spectra.spectral_tail` from the harmonic magnitudes (2K+1,)."""
    K = (mag.shape[0] - 1) // 2
    scale = mag.max()
    if K == 0 or scale == 0.0:
        return 0.0
    width = max(1, (K + 3) // 4)
    return float(max(mag[:width].max(), mag[-width:].max()) / scale)


def _check_finite(**spectra: np.ndarray) -> None:
    if np.isfinite(sum(X.sum() for X in spectra.values())):  # a NaN or inf entry makes the sum non-finite
        return
    for name, X in spectra.items():
        bad = ~np.isfinite(X)
        if bad.any():
            k = int(np.argwhere(bad)[0][0]) - (X.shape[0] - 1) // 2
            raise InputError(f"the {name} spectrum has NaN or inf (harmonic {k}); the coefficients must be finite: "
                             "check the model or the samples it was built from")


def coefficient_band(m: int, *spectra: np.ndarray, magnitudes: list[np.ndarray] | None = None) -> int:
    """Highest coefficient harmonic (<= 2m) above BAND_RTOL of its own spectrum's largest
    harmonic, over spectra (2K+1, ...) or their harmonic magnitudes (2K+1,) when given."""
    band = 0
    for mag in magnitudes if magnitudes is not None else map(_harmonic_magnitudes, spectra):
        K = (mag.shape[0] - 1) // 2
        big = np.nonzero(mag > BAND_RTOL * max(mag.max(), np.finfo(float).tiny))[0]
        if big.size:
            band = max(band, int(np.abs(big - K).max()))
    return min(band, 2 * m)


def _take(X: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Coefficients X_d for offsets d (zero outside the stored range), (len(d), ...)."""
    K = (X.shape[0] - 1) // 2
    inside = np.abs(d) <= K
    if inside.all():
        return X[d + K].astype(complex, copy=False)
    out = np.zeros((d.size,) + X.shape[1:], dtype=complex)
    out[inside] = X[d[inside] + K]
    return out


def first_order_matrix(W: np.ndarray, V: np.ndarray, Mh_lu=None, identity: bool = True) -> np.ndarray:
    """Dense first-order Hill matrix A = [[0, I], [-Mh^-1 W, -Mh^-1 V]] (2N, 2N) complex
    (identity=False leaves out the I block, for the higher terms of a polynomial in omega)."""
    N = W.shape[0]
    if Mh_lu is not None:
        W, V = sla.lu_solve(Mh_lu, W), sla.lu_solve(Mh_lu, V)
    A = np.zeros((2 * N, 2 * N), dtype=complex)
    if identity:
        A[:N, N:] = np.eye(N)
    A[N:, :N] = -W
    A[N:, N:] = -V
    return A


class _OnPattern:
    """Harmonic count m and coordinate count n of an operator on a block pattern."""

    pattern: BlockPattern

    @property
    def m(self) -> int:
        return self.pattern.m

    @property
    def n(self) -> int:
        return self.pattern.n


@dataclass(frozen=True, eq=False)
class HillOperator(_OnPattern):
    """The Hill/HB operator at one speed omega (rad/s).

    Blocks on ``pattern`` (each (nb, n, n) complex): W (the HB matrix of eq. 18), V and
    Mh (eq. 27); ``.W``, ``.V``, ``.Mh`` give them as (2m+1)n square CSC matrices.
    rhs: ((2m+1)n,) force harmonics; identity_mass: Mh is the identity (inverse-mass form);
    real_first_order: the real form (2(2m+1)n square) of the first-order Hill matrix when
    it was evaluated from precomputed polynomial terms, else None (built on demand).
    """

    omega: float
    pattern: BlockPattern
    blocks: tuple[np.ndarray, np.ndarray, np.ndarray]
    rhs: np.ndarray
    identity_mass: bool
    real_first_order: np.ndarray | None = None

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
        """Block matrix 0 (W), 1 (V) or 2 (Mh) as a dense ((2m+1)n)^2 array."""
        return self.pattern.dense(self.blocks[which])

    def real_first_order_matrix(self) -> np.ndarray:
        """The first-order Hill matrix [[0, I], [-Mh^-1 W, -Mh^-1 V]] in the real basis."""
        if self.real_first_order is not None:
            return self.real_first_order
        lu = None if self.identity_mass else sla.lu_factor(self.dense(2))
        return real_form(first_order_matrix(self.dense(0), self.dense(1), lu), self.m, self.n)


def _horner(terms: np.ndarray, w: float) -> np.ndarray:
    """sum_p w^p terms[p] (Horner's scheme) for terms (P, ...)."""
    out = terms[-1]
    for term in terms[-2::-1]:
        out = out * w + term
    return out


@dataclass(frozen=True, eq=False)
class HarmonicOperator(_OnPattern):
    """Hill/HB blocks of a system with coefficients polynomial in omega, on ``pattern``.

    spectra: the coefficient spectra (mass (2K+1, n, n), damping and stiffness (2K+1, n, n, P)
    with the powers of omega last) the blocks are made of; rhs: (Pf, (2m+1)n) force
    harmonics per power; identity_mass: Mh is the identity. The blocks W: (PW, nb, n, n),
    V: (PV, nb, n, n) complex, the coefficients of w^p (module docstring), and Mh: (nb, n, n),
    and the terms derived from them (band storage, real dense HB, real first-order Hill)
    are built on first use and kept (a large model whose HB and stability are reduced never
    builds them: O(m^2 n^2) memory).
    """

    pattern: BlockPattern
    spectra: tuple[np.ndarray, np.ndarray, np.ndarray]
    rhs: np.ndarray
    identity_mass: bool

    @property
    def powers(self) -> int:
        """PW, the number of omega powers of W (without building it)."""
        return max(self.spectra[2].shape[-1] - 1, self.spectra[1].shape[-1], 2) + 1

    @cached_property
    def _blocks(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        mass, damping, stiffness = self.spectra
        pat = self.pattern
        K = (mass.shape[0] - 1) // 2
        d = pat.k_index - pat.l_index + K  # |k - l| <= band <= K: every offset is stored
        l = pat.l_index[:, None, None].astype(float)
        Md, Cd, Kd = mass[d], damping[d], stiffness[d]
        Pc, Pk = damping.shape[-1], stiffness.shape[-1]
        W = np.zeros((self.powers,) + Md.shape, dtype=complex)
        V = np.zeros((max(Pc - 1, 1) + 1,) + Md.shape, dtype=complex)
        for p in range(Pk):
            W[p] += Kd[..., p]
        for p in range(Pc):
            W[p + 1] += 1j * l * Cd[..., p]
            V[p] += Cd[..., p]
        W[2] -= l**2 * Md
        V[1] += 2j * l * Md
        return W, V, Md.astype(complex, copy=False)

    @property
    def W(self) -> np.ndarray:
        return self._blocks[0]

    @property
    def V(self) -> np.ndarray:
        return self._blocks[1]

    @property
    def Mh(self) -> np.ndarray:
        return self._blocks[2]

    @classmethod
    def from_power_spectra(cls, mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, force: np.ndarray,
                           m: int, band: int | None = None) -> HarmonicOperator:
        """From spectra (2K+1, ...) with the powers of omega on the last axis: mass
        (2K+1, n, n), damping/stiffness (2K+1, n, n, P), force (2K+1, n, P); band: the
        coefficient band when already known (default: :func:`coefficient_band` per power)."""
        _check_finite(mass=mass, damping=damping, stiffness=stiffness, force=force)
        n = mass.shape[1]
        if band is None:
            band = coefficient_band(m, mass, *(damping[..., p] for p in range(damping.shape[-1])),
                                    *(stiffness[..., p] for p in range(stiffness.shape[-1])))
        pat = block_pattern(m, n, band)
        K = (mass.shape[0] - 1) // 2
        rhs = np.stack([_take(force[..., p], np.arange(-m, m + 1)).reshape(-1) for p in range(force.shape[-1])])
        identity = bool(np.count_nonzero(mass) == n and np.array_equal(mass[K], np.eye(n)))
        return cls(pat, (mass, damping, stiffness), rhs, identity)

    @classmethod
    def for_system(cls, system: RheoLinear, harmonics: int, form: str = "direct") -> HarmonicOperator:
        """The operator of one rheo-linear system (constant spectra), after checking m and
        the sampling; form "direct" (M, C, K) or "inverse-mass" (I, P, Q, eq. 16)."""
        m = check_harmonics(harmonics)
        if not isinstance(system, RheoLinear):
            raise InputError(f"expected a periodyn.RheoLinear system, got {type(system).__name__}; "
                             "build one with RheoLinear.from_functions/from_samples or model.at(omega)")
        S = system.spectra if check_form(form) == "direct" else system.inverse_mass_spectra
        band = coefficient_band(m, magnitudes=check_sampling(system.samples, m, S.mass, S.damping, S.stiffness))
        return cls.from_power_spectra(S.mass, S.damping[..., None], S.stiffness[..., None], S.force[..., None], m,
                                      band)

    @classmethod
    def for_model(cls, model: OmegaSplitModel, harmonics: int, form: str = "direct") -> HarmonicOperator:
        """The operator of a constant-speed model (polynomial in omega), checked as above."""
        m, form = check_harmonics(harmonics), check_form(form)
        Ms, Cs, Ks, fs, _ = model._power_spectra
        if form == "inverse-mass":
            Minv = np.linalg.inv(model.mass)
            Cs = fourier_coefficients(np.einsum("pij,pjkq->pikq", Minv, np.moveaxis(model.damping, 0, -1)))
            Ks = fourier_coefficients(np.einsum("pij,pjkq->pikq", Minv, np.moveaxis(model.stiffness, 0, -1)))
            fs = fourier_coefficients(np.einsum("pij,pjq->piq", Minv, np.moveaxis(model.force, 0, -1)))
            Ms = np.zeros_like(Ms)
            Ms[(Ms.shape[0] - 1) // 2] = np.eye(model.n)
        check_sampling(model.samples, m, Ms, Cs, Ks)
        return cls.from_power_spectra(Ms, Cs, Ks, fs, m)

    def _powers(self, omegas: np.ndarray, count: int) -> np.ndarray:
        return np.asarray(omegas, float)[..., None] ** np.arange(count)

    def at(self, omega: float, real_first_order: bool = False) -> HillOperator:
        """The operator at speed omega (rad/s); real_first_order: evaluate the real
        first-order Hill matrix from its precomputed terms (for repeated dense Hill)."""
        w = float(omega)
        real = _horner(self.real_first_order_terms, w) if real_first_order else None
        return HillOperator(w, self.pattern, (_horner(self.W, w), _horner(self.V, w), self.Mh), _horner(self.rhs, w),
                            self.identity_mass, real)

    def at_many(self, omegas) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Blocks W, V (S, nb, n, n) and force harmonics (S, (2m+1)n) at speeds (S,)."""
        pw = self._powers(omegas, len(self.W))
        return (np.einsum("sp,pbij->sbij", pw, self.W), np.einsum("sp,pbij->sbij", pw[:, : len(self.V)], self.V),
                pw[:, : len(self.rhs)] @ self.rhs)

    def mean_blocks_many(self, omegas) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The mean system's blocks (k = l = 0): W, V (S, n, n) at speeds (S,) and Mh (n, n)."""
        c, pw = self.pattern.centre_block, self._powers(omegas, len(self.W))
        return (np.einsum("sp,pij->sij", pw, self.W[:, c]), np.einsum("sp,pij->sij", pw[:, : len(self.V)], self.V[:, c]),
                self.Mh[c])

    def balance_scales_many(self, omegas) -> tuple[np.ndarray, np.ndarray]:
        """Per row of the HB matrix (complex basis, row (k + m) n + i) the largest modulus
        of the omega-power terms it sums, ``max_p |w|^p max_j |W_p[row, j]|`` (S, N), and
        the right-hand sides (S, N), at speeds (S,): the sizes an undamped resonance cancels."""
        pw = self._powers(omegas, len(self.W))
        return np.max(np.abs(pw)[:, :, None] * self._row_terms[None], axis=1), pw[:, : len(self.rhs)] @ self.rhs

    @cached_property
    def _row_terms(self) -> np.ndarray:
        """max_j |W_p[row, j]| per omega power and row, (PW, N)."""
        pat, n = self.pattern, self.W.shape[2]
        out = np.zeros((len(self.W), pat.size // n, n))
        for p, Wp in enumerate(self.W):
            np.maximum.at(out[p], pat.k_index - pat.k_index.min(), np.abs(Wp).max(axis=2))
        return out.reshape(len(self.W), pat.size)

    def banded_many(self, omegas) -> tuple[np.ndarray, np.ndarray]:
        """HB matrices in LAPACK band storage (S, 2u+1, N) and right-hand sides (S, N)."""
        pw = self._powers(omegas, len(self.W))
        return np.einsum("sp,prc->src", pw, self.banded_terms), pw[:, : len(self.rhs)] @ self.rhs

    def real_balance_many(self, omegas) -> tuple[np.ndarray, np.ndarray]:
        """HB matrices (S, N, N) and right-hand sides (S, N) in the real basis."""
        pw = self._powers(omegas, len(self.W))
        return np.einsum("sp,pij->sij", pw, self.real_balance_terms), pw[:, : len(self.rhs)] @ self.real_rhs

    def real_first_order_many(self, omegas) -> np.ndarray:
        """Real first-order Hill matrices (S, 2N, 2N) at speeds (S,)."""
        pw = self._powers(omegas, len(self.W))
        return np.einsum("sp,pij->sij", pw, self.real_first_order_terms)

    @cached_property
    def banded_terms(self) -> np.ndarray:
        """W_p in band storage, (PW, 2u+1, N)."""
        return np.stack([self.pattern.banded(Wp) for Wp in self.W])

    @cached_property
    def real_balance_terms(self) -> np.ndarray:
        """W_p as real dense matrices, (PW, N, N)."""
        return np.stack([real_form(self.pattern.dense(Wp), self.m, self.n, halves=1) for Wp in self.W])

    @cached_property
    def real_rhs(self) -> np.ndarray:
        """Force terms in the real basis, (Pf, N)."""
        return to_real_basis(self.rhs.T, self.m, self.n, halves=1).T

    @cached_property
    def real_first_order_terms(self) -> np.ndarray:
        """A_p = [[0, I if p = 0], [-Mh^-1 W_p, -Mh^-1 V_p]] in the real basis, (PW, 2N, 2N)."""
        pat = self.pattern
        lu = None if self.identity_mass else sla.lu_factor(pat.dense(self.Mh))
        V = np.concatenate([self.V, np.zeros((len(self.W) - len(self.V),) + self.V.shape[1:], dtype=complex)])
        return np.stack([real_form(first_order_matrix(pat.dense(Wp), pat.dense(Vp), lu, identity=(p == 0)),
                                   self.m, self.n) for p, (Wp, Vp) in enumerate(zip(self.W, V))])
