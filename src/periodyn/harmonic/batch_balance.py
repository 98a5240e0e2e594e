"""Harmonic balance at many speeds of one omega-polynomial operator (a sweep's HB).

:class:`BalanceBatch` is built once per model from a :class:`HarmonicOperator` and solves
the HB systems ``W(w) x = f(w)`` of a chunk of speeds together, by one of three paths:

- "banded": narrow, small bands; the jitted banded LU of :mod:`periodyn.kernels.solvers.banded`
  over the speeds;
- "dense": stacked real LAPACK solves of the real HB matrices, evaluated from their
  precomputed omega-power terms (the band couples nearly all harmonics: small systems, and
  large ones whose dense LU is cheaper than the banded one while the terms fit in
  DENSE_TERMS_BYTES; a chunk of a large one is a single speed). When the
  coefficients have a half-period symmetry ``X(theta + pi) = P X(theta) P``, P = diag(s)
  (:func:`periodyn.stability.magnus.half_period_signs` of M, C and K), harmonic l of coordinate
  i couples only to harmonics l' of coordinates j with ``(-1)^l s_i = (-1)^l' s_j``: the
  real HB matrix is block-diagonal in these two classes (the couplings between them are
  below 1e-12 of the largest entry, i.e. round-off of the sampled spectra) and is solved
  as two systems of half the size, about a quarter of the work. A class the forcing does
  not reach (its force harmonics below 1e-12 of the largest at every power of omega) has
  the zero solution and is not solved. A class of ITERATIVE_MIN rows or more is solved by
  GMRES (:func:`periodyn.numerics.krylov.gmres`, relative residual GMRES_RTOL) right-
  preconditioned with the single-precision LU of its matrix at a previous speed (the
  reference, kept between chunks): the matrix is an omega-polynomial, so near the
  reference speed ``A(w_ref)^-1 A(w)`` is close to the identity and a few steps (about
  N^2 flops each) replace an LU (N^3). Where GMRES_STEPS steps do not reach the
  tolerance the speed's own matrix is factorized and becomes the reference (and where
  that does not converge either, a double-precision LU solves the speed directly);
- None: speed by speed with :func:`periodyn.harmonic.balance.solve_balance` (banded LAPACK, dense or
  sparse LU, whichever :func:`periodyn.harmonic.balance.balance_storage` estimates cheapest).

Every path checks every speed as the per-speed solve does (:func:`periodyn.harmonic.balance.balance_failure`):
an exactly or nearly singular HB matrix (an undamped resonance) or an inaccurate solve
fails its own speed, never the chunk.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
from scipy.linalg.lapack import dgetrf, dgetrs, sgetrf, sgetrs

from ..errors import ConvergenceError, InputError
from .balance import AMPLIFICATION_MAX, RESIDUAL_MAX, amplification, balance_failure, balance_storage, singular_balance, solve_balance
from ..kernels.solvers.banded import banded_solve_batch
from ..numerics.krylov import gmres
from .operator import HarmonicOperator
from .pattern import _real_form_indices, from_real_basis

__all__ = ["BalanceBatch", "symmetry_classes"]

DENSE_BALANCE_MAX = 400  # size of the largest (class) system up to which speeds are stacked dense
DENSE_TERMS_BYTES = 4e8  # memory of the real dense HB terms (PW, N, N) up to which a large dense HB takes them
JIT_BANDED_MAX = 20_000  # N u^2 up to which the jitted banded LU beats a LAPACK call per speed
COUPLING_RTOL = 1e-12  # couplings between symmetry classes below this fraction of the largest entry are round-off
ITERATIVE_MIN = 1000  # rows of a dense class system from which it is solved by GMRES with a reference LU
GMRES_RTOL = 1e-12  # relative residual of a GMRES solve
GMRES_STEPS = 16  # GMRES steps before the speed is factorized (about a tenth of an LU at ITERATIVE_MIN rows)
SINGLE_MAX = 1e30  # largest matrix entry for which the reference LU is taken in single precision


def symmetry_classes(m: int, n: int, signs: np.ndarray | None) -> tuple[np.ndarray, ...]:
    """Rows of the real HB basis (size (2m+1)n, see :func:`periodyn.harmonic.pattern.real_form`)
    in each half-period symmetry class: ``(-1)^l s_i = +1`` and ``= -1`` for row (l, i);
    one class of all rows without signs."""
    N = (2 * m + 1) * n
    if signs is None:
        return (np.arange(N),)
    zero, pos, _ = _real_form_indices(m, n, 1)
    harmonic_rows = np.concatenate([zero, pos, pos])  # the complex-basis row of each real-basis row
    l, i = np.divmod(harmonic_rows, n)
    parity = np.where((l - m) % 2 == 0, 1.0, -1.0) * np.asarray(signs)[i]
    return tuple(rows for rows in (np.flatnonzero(parity > 0), np.flatnonzero(parity < 0)) if rows.size)


class BalanceBatch:
    """The HB solves of one operator at many speeds. kind: the preferred path ("banded",
    "dense" or None, module docstring); signs: half-period signs (n,) of the coefficients
    or None."""

    def __init__(self, operator: HarmonicOperator, signs: np.ndarray | None = None):
        self.operator = op = operator
        pat = op.pattern
        self.storage = balance_storage(pat)
        self.signs = signs
        largest = max(rows.size for rows in symmetry_classes(op.m, op.n, signs))
        small = not pat.narrow and largest <= DENSE_BALANCE_MAX
        large = self.storage.kind == "dense" and 8.0 * op.powers * pat.size**2 <= DENSE_TERMS_BYTES
        self.kind = ("banded" if pat.narrow and pat.size * pat.half_bandwidth**2 <= JIT_BANDED_MAX else
                     "dense" if small or large else None)
        self.references: dict[int, tuple[np.ndarray, np.ndarray]] = {}  # LU of each large class at a past speed
        self.factorizations = 0  # LUs taken by the GMRES path (its speeds solved without one are the gain)

    @cached_property
    def dense_blocks(self) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]:
        """Per symmetry class reached by the forcing: its real-basis rows (k,), matrix terms
        (PW, k*k) and force terms (Pf, k); a single class of all rows when the classes do
        not decouple the real HB matrix."""
        op = self.operator
        terms, rhs = op.real_balance_terms, op.real_rhs
        classes = symmetry_classes(op.m, op.n, self.signs)
        if len(classes) > 1:
            a, b = classes
            cross = max(np.abs(terms[:, a][:, :, b]).max(), np.abs(terms[:, b][:, :, a]).max())
            if cross > COUPLING_RTOL * np.abs(terms).max():
                classes = (np.arange(terms.shape[1]),)
        blocks, forcing = [], np.abs(rhs).max(axis=0)
        for rows in classes:
            if len(classes) > 1 and forcing[rows].max() <= COUPLING_RTOL * forcing.max():
                continue  # not forced (round-off of the sampled force): zero solution
            whole = len(classes) == 1  # all rows: the terms themselves, not a copy
            sub = (terms if whole else np.ascontiguousarray(terms[:, rows][:, :, rows])).reshape(len(terms), -1)
            blocks.append((rows, sub, np.ascontiguousarray(rhs[:, rows])))
        return tuple(blocks)

    def solve_many(self, w: np.ndarray, kind: str | None = "preferred") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Harmonics (S, 2m+1, n) (zero where failed), relative HB residuals (S,) and
        failure messages (S,) ('' where solved) at speeds w (S,) rad/s; kind: the path
        ("preferred": :attr:`kind`)."""
        kind = self.kind if kind == "preferred" else kind
        op, m, n = self.operator, self.operator.m, self.operator.n
        message = np.full(w.size, "", dtype=object)
        if kind is None:
            return self._one_by_one(w, message)
        if kind == "banded":
            ab, b = op.banded_many(w)
            y, residual, failed = np.empty_like(b), np.empty(w.size), np.zeros(w.size, dtype=np.int64)
            banded_solve_batch(ab, b, y, residual, failed)
            for i in np.nonzero(failed)[0]:
                message[i] = str(singular_balance(w[i], f"zero pivot in column {failed[i] - 1}"))
            y[failed > 0] = 0.0
            q = y.reshape(-1, 2 * m + 1, n)
            q = 0.5 * (q + np.conj(q[:, ::-1]))  # the conjugate symmetry of a real solution
        else:
            pw = np.asarray(w, float)[:, None] ** np.arange(len(op.W))
            b = pw[:, : len(op.real_rhs)] @ op.real_rhs
            y, squares = np.zeros_like(b), np.zeros(w.size)
            for c, (rows, terms, rhs) in enumerate(self.dense_blocks):
                k = rows.size
                A = (pw @ terms).reshape(w.size, k, k)
                bc = pw[:, : len(rhs)] @ rhs
                if k >= ITERATIVE_MIN:
                    y[:, rows], r = self._krylov_solve(A, bc, w, message, c)
                else:
                    y[:, rows], r = _stacked_solve(A, bc, w, message)
                squares += r**2
            residual = np.sqrt(squares)
            q = from_real_basis(y[..., None], m, n, halves=1)[..., 0].reshape(-1, 2 * m + 1, n)
        scale = np.linalg.norm(b, axis=1)
        residual = np.where(scale > 0, residual / np.where(scale > 0, scale, 1.0), residual)
        row_scale, rhs = op.balance_scales_many(w)
        amplified = amplification(row_scale, q.reshape(w.size, -1), rhs)
        suspect = (message == "") & ~((residual <= RESIDUAL_MAX) & (amplified <= AMPLIFICATION_MAX))
        for i in np.flatnonzero(suspect):
            message[i] = balance_failure(w[i], residual[i], amplified[i], kind)
        q[message != ""] = 0.0
        return q, residual, message

    def _krylov_solve(self, A: np.ndarray, b: np.ndarray, w: np.ndarray, message: np.ndarray,
                      c: int) -> tuple[np.ndarray, np.ndarray]:
        """:func:`_stacked_solve` for the large class c: GMRES preconditioned with the
        reference LU of the class (single precision: half the memory traffic per step and
        half the factorization; GMRES on the double-precision matrix still reaches
        GMRES_RTOL), else with the LU of the speed's own matrix (the new reference); where
        that fails too (singular or too ill-conditioned in single precision, or entries
        beyond its range) the double-precision LU solves the speed directly."""
        y = np.zeros_like(b)
        for i in range(w.size):
            x = self._gmres(A[i], b[i], c)
            if x is None and np.abs(A[i]).max() < SINGLE_MAX:
                lu, piv, info = sgetrf(A[i].astype(np.float32))
                self.factorizations += 1
                self.references.pop(c, None)
                if info == 0:
                    self.references[c] = (lu, piv)
                    x = self._gmres(A[i], b[i], c)
            if x is None:
                lu, piv, info = dgetrf(A[i])
                self.factorizations += 1
                if info > 0:  # exactly singular (an undamped resonance)
                    message[i] = str(singular_balance(w[i], f"zero pivot in column {info - 1}"))
                    continue
                x = dgetrs(lu, piv, b[i])[0]
            y[i] = x
        return y, np.linalg.norm(np.einsum("sij,sj->si", A, y) - b, axis=1)

    def _gmres(self, A: np.ndarray, b: np.ndarray, c: int) -> np.ndarray | None:
        """x with |A x - b| <= GMRES_RTOL |b| by GMRES with the reference of class c, or None."""
        reference = self.references.get(c)
        if reference is None:
            return None
        x, rel, _ = gmres(A.__matmul__, b, lambda v: sgetrs(*reference, v.astype(np.float32))[0].astype(float),
                          rtol=GMRES_RTOL, max_steps=GMRES_STEPS)
        return x if rel <= GMRES_RTOL else None

    def _one_by_one(self, w: np.ndarray, message: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        op = self.operator
        q, residual = np.zeros((w.size, 2 * op.m + 1, op.n), complex), np.full(w.size, np.nan)
        for i, wi in enumerate(w):
            try:
                row_scale = op.balance_scales_many([wi])[0][0]
                q[i], residual[i] = solve_balance(op.at(wi), self.storage, row_scale)
            except (InputError, ConvergenceError) as exc:  # singular (InputError) or inaccurate
                message[i] = str(exc)
        return q, residual, message


def _stacked_solve(A: np.ndarray, b: np.ndarray, w: np.ndarray, message: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solutions (S, k) of the real systems A (S, k, k) y = b (S, k) and residual norms
    (S,); an exactly singular speed gets its message (and a zero solution), the others
    are solved one by one then."""
    try:
        y = np.linalg.solve(A, b[..., None])[..., 0]
    except np.linalg.LinAlgError:  # one exactly singular speed: solve the others one by one
        y = np.zeros_like(b)
        for i in range(w.size):
            try:
                y[i] = np.linalg.solve(A[i], b[i])
            except np.linalg.LinAlgError:
                message[i] = str(singular_balance(w[i], "LAPACK gesv"))
    return y, np.linalg.norm(np.einsum("sij,sj->si", A, y) - b, axis=1)
