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

import warnings
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from ..errors import ConvergenceError, InputError
from .operator import FORMS, AliasingWarning, HarmonicOperator, HillOperator, check_harmonics
from .truncation import (BALANCE_TRUNCATION_TOL, BalanceTruncationWarning, balance_truncation,
                         balance_truncation_message)
from .pattern import BlockPattern, from_real_basis, real_form, to_real_basis
from ..periodic import PeriodicSolution, output_spectrum
from ..system import RheoLinear

__all__ = ["PeriodicSolution", "periodic_solution", "AliasingWarning", "FORMS", "BalanceStorage", "balance_storage",
           "solve_balance", "check_harmonics", "amplification", "balance_failure"]


def singular_balance(omega: float, detail: str) -> InputError:
    """The error for an exactly singular HB matrix at omega (rad/s)."""
    return InputError(f"the harmonic balance matrix is singular at omega = {omega:.6g} rad/s (an undamped "
                      f"resonance: a characteristic exponent is a multiple of i*omega); add damping or move omega "
                      f"({detail})")


RESIDUAL_MAX = 1e-6  # relative HB residual above which an LU solve failed (backward-stable: ~1e-15)
AMPLIFICATION_MAX = RESIDUAL_MAX / np.finfo(float).eps  # ~4.5e9: condition at which rounding may cost 10 digits


def amplification(row_scale, x, rhs) -> np.ndarray:
    """||x||_inf / max_i(|rhs_i| / row_scale_i) over the last axis (complex basis; row_scale
    from :meth:`HarmonicOperator.balance_scales_many`): how much the HB solve amplifies the
    forcing relative to the terms each row balances, a lower bound of the condition number
    of the term-scaled matrix; 0 without forcing. Cancellation of the terms of a row (an
    undamped resonance) makes it large, bad scaling between rows does not."""
    scale = np.asarray(row_scale)
    rel = np.abs(rhs) / np.where(scale > 0, scale, np.inf)
    bottom = rel.max(axis=-1)
    return np.where(bottom > 0, np.abs(x).max(axis=-1) / np.where(bottom > 0, bottom, 1.0), 0.0)


def balance_failure(omega: float, residual: float, amplified: float, kind: str) -> str:
    """Why the HB solve at omega (rad/s) is not a result ('' if it is): a relative
    residual above RESIDUAL_MAX (also NaN), or a forcing amplified more than
    AMPLIFICATION_MAX times, i.e. omega within rounding of an undamped resonance."""
    if not residual <= RESIDUAL_MAX:
        return (f"the harmonic balance solve ({kind}) at omega = {omega:.6g} rad/s gave a non-finite or inaccurate "
                f"solution (relative residual {residual:.3g}); the HB matrix is numerically singular or overflows "
                "(add damping, move omega or rescale the model)")
    if amplified > AMPLIFICATION_MAX:
        return (f"the harmonic balance matrix at omega = {omega:.6g} rad/s is nearly singular: the forcing is "
                f"amplified {amplified:.3g} times relative to the terms it balances (a lower bound of its "
                "condition number), so "
                "rounding may leave fewer than 6 correct digits of a huge response: omega is at an undamped resonance "
                "(a characteristic exponent within rounding of a multiple of i*omega); add damping or move omega")
    return ""
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


def solve_balance(op: HillOperator, storage: BalanceStorage | None = None,
                  row_scale: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """Solve W x = rhs with the storage of :func:`balance_storage` (or the one given);
    row_scale (N,): the term sizes of each row (:meth:`HarmonicOperator.balance_scales_many`),
    with which a solve at an undamped resonance is refused.
    Returns harmonics (2m+1, n) and the relative residual; a non-finite or inaccurate
    solution, or one at an undamped resonance (:func:`balance_failure`), raises
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
    amplified = 0.0 if row_scale is None else float(amplification(row_scale, x, op.rhs))
    failure = balance_failure(op.omega, residual, amplified, kind)
    if failure:
        raise ConvergenceError(failure, residual=residual, iterations=1)
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
    Warns (BalanceTruncationWarning) where the harmonics left out are not small
    (:mod:`periodyn.harmonic.truncation`).
    """
    m = check_harmonics(harmonics)
    row_scale = None
    if operator is None:
        harmonic = HarmonicOperator.for_system(system, m, form)
        operator, row_scale = harmonic.at(system.omega), harmonic.balance_scales_many([system.omega])[0][0]
    q, residual = solve_balance(operator, row_scale=row_scale)
    S = system.spectra
    truncation = balance_truncation(S.mass, S.damping[None], S.stiffness[None], S.force[None], q[None],
                                    [system.omega])[0]
    if truncation > BALANCE_TRUNCATION_TOL:
        warnings.warn(balance_truncation_message(truncation, m, system.omega), BalanceTruncationWarning, stacklevel=2)
    return PeriodicSolution(system.omega, q, output_spectrum(system.spectra.outputs, q), system.coordinate_names,
                            system.output_names, residual, form)
