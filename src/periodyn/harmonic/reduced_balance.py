"""Harmonic balance of a large element model on its mean-system modes, certified by the
residual of the full HB equations.

In the coordinates q = Phi x of all n mean-system modes (:func:`periodyn.model.reduce.mean_modes`,
M-orthonormal), split into the k kept (l) and the truncated (h), the HB equations
``W(w) q = f(w)`` (:mod:`periodyn.harmonic.operator`) are solved by the preconditioned
iteration (block Gauss-Seidel, kept modes first)

    r = Phi^T (f - W Phi x),   y_l = W_ll^-1 r_l,   y_h = D^-1 (r_h - W_hl y_l),   x <- x + y,
    D_a = -(a w)^2 Mbar_hh + i a w Cbar_hh + Kbar_hh      (a = -m..m, its diagonal),

from x = 0: the first step is the reduced HB on the kept modes plus the static-plus-dynamic
correction of the truncated ones by the diagonal of their mean block, driven by the
residual the kept step leaves (W_hl y_l costs P n k per term, by the kept modes' columns
of the samples); the following steps correct the remaining coupling. Against block Jacobi
(y_h = D^-1 r_h) the first residual is 20-40x smaller and a speed takes about 3 residuals
instead of 4 (slider-crank, 32-128 rod elements, k = 10, m = 12). The residual
``f - W q`` of the FULL equations is evaluated per iteration by alternating frequency-time products on P = band + 2m + 1 angles
(exact: no product of a coefficient harmonic |d| <= band with a response harmonic |b| <= m
aliases onto a balanced harmonic |a| <= m), O(P n^2) per speed instead of an
O(((2m+1) n)^3) LU. The iterates and residuals are those of a real solution, kept as
their harmonics a = 0..m (a < 0: the conjugates). A speed whose relative residual does not
reach RTOL within ITERATIONS steps is reported as not converged (the caller solves it in full).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ..model.reduce import MeanModes, project
from ..numerics.spectra import half_synthesis, sample_angles, synthesize
from ..system import OmegaSplitModel
from .operator import HarmonicOperator
from .pattern import from_real_basis, to_real_basis
from .truncation import above_noise, coefficient_terms

__all__ = ["ReducedBalance", "RTOL", "ITERATIONS"]

RTOL = 1e-10  # relative residual |f - W q| / |f| of the full HB equations at which a speed is solved
ITERATIONS = 12  # residual evaluations before a speed is handed to the full solve


class ReducedBalance:
    """Per-model data of the reduced HB: the full model's coefficients resampled on
    P = band + 2m + 1 angles ((P, n, n) per term M, C_p, K_p), their mean blocks and the noise
    floors of their harmonics, the mean modal diagonal and the kept block's HB operator per
    mode count (built on first use).

    model: the OmegaSplitModel; m: harmonics; band: the coefficient band of the full HB
    operator (its harmonics above it are dropped, as the operator does); modes: the model's
    :class:`~periodyn.model.reduce.MeanModes`."""

    def __init__(self, model: OmegaSplitModel, m: int, band: int, modes: MeanModes):
        self.model, self.m, self.n, self.modes = model, m, model.n, modes
        Ms, Cs, Ks, fs, _ = model._power_spectra
        self.P = P = band + 2 * m + 1
        theta = sample_angles(P)
        K = (Ms.shape[0] - 1) // 2
        d = np.arange(-band, band + 1)

        terms, self.mags, self.floors, self.exponents = coefficient_terms(Ms, Cs, Ks)
        self.powers = Pc, Pk = Cs.shape[-1], Ks.shape[-1]
        # per coordinate row, the largest coefficient of the terms of the HB matrix's rows per
        # power of omega they multiply (stiffness; damping times m; mass times m^2), (PW, n)
        self.row_terms = np.zeros((max(Pk, Pc + 1, 3), self.n))
        for p in range(Pk):
            self.row_terms[p] = np.abs(Ks[d + K, ..., p]).max(axis=(0, 2))
        for p in range(Pc):
            self.row_terms[p + 1] = np.maximum(self.row_terms[p + 1], m * np.abs(Cs[d + K, ..., p]).max(axis=(0, 2)))
        self.row_terms[2] = np.maximum(self.row_terms[2], m * m * np.abs(Ms[d + K]).max(axis=(0, 2)))
        self.theta, self.terms = theta, [X[K - band: K + band + 1] for X in terms]
        self.mean_stack = np.stack([X[K].real for X in terms])  # their mean blocks, (Q, n, n)
        self.derivative = np.array([0] + [1] * Pc + [2] * Pk)  # the samples a term multiplies: q'', q' or q
        self.real_synthesis = half_synthesis(m, theta)  # a real solution's harmonics a >= 0 suffice, (P, 2(m+1))
        analysis = np.exp(-1j * np.outer(np.arange(m + 1), theta)) / P  # harmonics a = 0..m of samples, (m+1, P)
        self.analysis = np.concatenate([analysis.real, analysis.imag])  # real and imaginary parts, (2(m+1), P)
        self.force = np.stack([fs[np.arange(-m, m + 1) + K, :, p] for p in range(fs.shape[-1])])  # (Pf, 2m+1, n)
        Phi = modes.shapes
        self.mean_diagonals = [np.einsum("ni,nm,mi->i", Phi, X.mean(axis=0), Phi)
                               for X in (model.mass, *model.damping, *model.stiffness)]
        self._kept: dict[int, HarmonicOperator] = {}
        self._stacked: dict[tuple[int, ...], np.ndarray] = {}
        self._modal: dict[tuple[int, tuple[int, ...]], np.ndarray] = {}
        self._modal_means: dict[int, np.ndarray] = {}

    def stacked(self, taken: tuple[int, ...]) -> np.ndarray:
        """The terms ``taken`` at the P angles side by side, (P, n, T n) (one matrix product per
        angle for all of them; built once per set of terms: the products take only the terms
        with harmonics above noise)."""
        if taken not in self._stacked:
            self._stacked[taken] = np.concatenate([synthesize(self.terms[t], self.theta) for t in taken], axis=2)
        return self._stacked[taken]

    def kept_operator(self, k: int) -> HarmonicOperator:
        """The HB operator of the model projected on its k lowest mean modes."""
        if k not in self._kept:
            self._kept[k] = HarmonicOperator.for_model(project(self.model, self.modes.shapes[:, :k]), self.m)
        return self._kept[k]

    def row_scales(self, w: np.ndarray) -> np.ndarray:
        """Per row of the HB matrix (complex basis, harmonic-major) the largest modulus of the
        terms it sums, max_p |w|^p row_terms[p] (S, (2m+1) n), at speeds w (S,): the scales of
        :func:`periodyn.harmonic.balance.amplification` (from the coefficients' magnitudes,
        without the HB matrix)."""
        scale = np.max(np.abs(w)[:, None, None] ** np.arange(len(self.row_terms))[:, None] * self.row_terms, axis=1)
        return np.tile(scale, (1, 2 * self.m + 1))

    def forcing(self, w: np.ndarray) -> np.ndarray:
        """Force harmonics (S, 2m+1, n) at speeds w (S,)."""
        return np.tensordot(w[:, None] ** np.arange(len(self.force)), self.force, 1)

    def terms_at(self, w: np.ndarray) -> tuple[np.ndarray, list[int], np.ndarray]:
        """The terms taken per angle at speeds w (S,) (bool (Q,): harmonics above noise at one
        of them, :func:`~periodyn.harmonic.truncation.above_noise`), the derivatives (0 q'',
        1 q', 2 q) the other terms multiply, and per speed the sums of their mean blocks times
        w^p per derivative, side by side (S, n, G n) (their harmonics are the samples'
        rounding noise, 1e-14 to 3e-13 of their largest entry)."""
        used = above_noise(self.mags, self.floors, self.exponents, w).any(axis=0)
        order = sorted({int(self.derivative[t]) for t in np.flatnonzero(~used)})
        return used, order, self._mean_sums(w, used, order, self.mean_stack)

    def _mean_sums(self, w: np.ndarray, used: np.ndarray, order: list[int], stack: np.ndarray) -> np.ndarray:
        """Per speed w (S,) the sums of the blocks stack (Q, r, c) of the terms not used times
        w^p per derivative in order, side by side (S, r, G c) (each as one matrix product)."""
        blocks = np.empty((w.size,) + stack.shape[1:2] + (len(order),) + stack.shape[2:])
        for g, d in enumerate(order):
            t = np.flatnonzero(~used & (self.derivative == d))
            blocks[:, :, g] = np.tensordot(w[:, None] ** self.exponents[t], stack[t], 1)
        return blocks.reshape(w.size, stack.shape[1], -1)

    def residual(self, w: np.ndarray, q: np.ndarray, f: np.ndarray, terms=None) -> np.ndarray:
        """f - W(w) q (S, m+1, n) of the full HB equations, harmonics a = 0..m, for the
        harmonics a = 0..m of a real solution q (S, m+1, n) and force f (S, m+1, n): per
        angle the samples of the terms taken (``terms``: :meth:`terms_at` of w) times those
        of q'', w^p q' or w^p q, plus the other terms' mean blocks times the harmonics."""
        used, order, blocks = self.terms_at(w) if terms is None else terms
        return f - self._product(w, q, self.stacked(tuple(int(t) for t in np.flatnonzero(used))), used, order, blocks)

    def coupling_terms(self, w: np.ndarray, k: int, terms) -> tuple:
        """The data of :meth:`coupling` at speeds w (S,) with k kept modes: the terms taken and
        the derivatives of the others (``terms``: :meth:`terms_at` of w), the samples Phi^T X_t
        Phi_l of the terms taken side by side (P, n, T k) (built once per k and set of terms)
        and the other terms' summed modal mean blocks per speed (S, n, G k)."""
        used, order, _ = terms
        taken = tuple(int(t) for t in np.flatnonzero(used))
        Phi = self.modes.shapes
        if (k, taken) not in self._modal:
            X, n = self.stacked(taken), self.n
            self._modal[k, taken] = np.concatenate([Phi.T @ (X[:, :, i * n: (i + 1) * n] @ Phi[:, :k])
                                                    for i in range(len(taken))], axis=2)
        if k not in self._modal_means:  # Phi^T Xbar_t Phi_l, (Q, n, k)
            self._modal_means[k] = np.einsum("ni,qnj->qij", Phi, self.mean_stack @ Phi[:, :k], optimize=True)
        return used, order, self._modal[k, taken], self._mean_sums(w, used, order, self._modal_means[k])

    def coupling(self, w: np.ndarray, x: np.ndarray, terms) -> np.ndarray:
        """Phi^T W(w) Phi_l x (S, m+1, n) in modal coordinates, harmonics a = 0..m, of the
        kept modes' harmonics x (S, m+1, k) (the kept modes' columns of the terms: P n k work
        per term, k/n of a residual's); ``terms``: :meth:`coupling_terms` of w and k."""
        used, order, stacked, blocks = terms
        return self._product(w, x, stacked, used, order, blocks)

    def _product(self, w, q, stacked, used, order, blocks) -> np.ndarray:
        """W(w) q (S, m+1, r) of harmonics q (S, m+1, c) by the samples of the terms taken
        (stacked (P, r, T c)) and the other terms' summed mean blocks (S, r, G c)."""
        S, c, r = w.size, q.shape[-1], stacked.shape[1]
        jw = 1j * np.arange(self.m + 1)[None, :, None] * w[:, None, None]
        Z = np.concatenate([jw * jw * q, jw * q, q], axis=2)  # harmonics of q'', q', q, (S, m+1, 3c)
        out = np.zeros((S, self.m + 1, r), dtype=complex)
        taken = np.flatnonzero(used)
        if taken.size:  # the samples of q'', w^p q' or w^p q of each term taken, (S, P, T c)
            y = np.matmul(self.real_synthesis, np.concatenate([Z.real, Z.imag], axis=1))  # their samples, (S, P, 3c)
            z = np.concatenate([y[:, :, d * c: (d + 1) * c] * w[:, None, None] ** self.exponents[t]
                                for t in taken for d in [self.derivative[t]]], axis=2)
            p = np.matmul(stacked, np.ascontiguousarray(z.transpose(1, 2, 0)))  # (P, r, S)
            h = (self.analysis @ p.reshape(self.P, -1)).reshape(2, self.m + 1, r, S)  # by one real product
            out += (h[0] + 1j * h[1]).transpose(2, 0, 1)
        if order:  # a constant block's product with the harmonics, per harmonic
            Y = np.concatenate([Z[:, :, d * c: (d + 1) * c] for d in order], axis=2)  # (S, m+1, G c)
            mean = np.matmul(np.concatenate([Y.real, Y.imag], axis=1), blocks.transpose(0, 2, 1))
            out += mean[:, : self.m + 1] + 1j * mean[:, self.m + 1:]
        return out

    def diagonal(self, w: np.ndarray) -> np.ndarray:
        """diag D_a of the mean modal block at speeds w (S,), (S, 2m+1, n)."""
        Pc, Pk = self.powers
        M, C, K = self.mean_diagonals[0], self.mean_diagonals[1: 1 + Pc], self.mean_diagonals[1 + Pc:]
        c = sum(w[:, None] ** p * Cp for p, Cp in enumerate(C))
        kk = sum(w[:, None] ** p * Kp for p, Kp in enumerate(K))
        s = 1j * np.arange(-self.m, self.m + 1)[None, :, None] * w[:, None, None]
        return s * s * M + s * c[:, None, :] + kk[:, None, :]

    def solve_many(self, w: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Physical harmonics (S, 2m+1, n), relative residuals of the full HB equations (S,)
        and the residual evaluations taken (S,; 0 where RTOL was not reached in ITERATIONS)
        at speeds w (S,) rad/s with k kept modes."""
        m, n, S = self.m, self.n, w.size
        Phi = self.modes.shapes
        op = self.kept_operator(k)
        kept = [sla.lu_factor(A, check_finite=False) for A in op.real_balance_many(w)[0]]
        D = self.diagonal(w)[:, m:, k:]
        f = self.forcing(w)
        scale = np.linalg.norm(f.reshape(S, -1), axis=1)
        scale = np.where(scale > 0, scale, 1.0)
        f = 0.5 * (f + np.conj(f[:, ::-1]))[:, m:]  # harmonics a >= 0 of a real force
        weight = np.where(np.arange(m + 1) > 0, 2.0, 1.0)[None, :, None]  # |v|^2 = sum_a>=0 weight_a |v_a|^2
        used, order, blocks = self.terms_at(w)
        coupled = self.coupling_terms(w, k, (used, order, blocks)) if k < n else None
        x = np.zeros((S, m + 1, n), dtype=complex)
        q = np.zeros_like(x)
        r = f
        rel = np.full(S, np.inf)
        steps = np.zeros(S, dtype=int)
        todo = np.arange(S)
        for it in range(1, ITERATIONS + 1):
            rm = _times_real(r, Phi)  # modal residual Phi^T r, (s, m+1, n)
            b = to_real_basis(_mirror(rm[:, :, :k], axis=1).reshape(todo.size, -1).T, m, k, halves=1)  # (N, s)
            for j, s in enumerate(todo):
                b[:, j] = sla.lu_solve(kept[s], b[:, j], check_finite=False)
            y = from_real_basis(b, m, k, halves=1).T.reshape(todo.size, 2 * m + 1, k)[:, m:]
            x[todo, :, :k] += y
            if k < n:  # the truncated modes' residual after the kept step (Gauss-Seidel)
                rm = rm[:, :, k:] - self.coupling(w[todo], y, (*coupled[:3], coupled[3][todo]))[:, :, k:]
                x[todo, :, k:] += rm / D[todo]
            x[todo, 0] = x[todo, 0].real  # the mean of a real solution (its rounding in the solves)
            q[todo] = _times_real(x[todo], Phi.T)
            r = self.residual(w[todo], q[todo], f[todo], (used, order, blocks[todo]))
            rel[todo] = np.sqrt((weight * np.abs(r) ** 2).sum(axis=(1, 2))) / scale[todo]
            done = rel[todo] <= RTOL
            steps[todo[done]] = it
            todo, r = todo[~done], r[~done]
            if not todo.size:
                break
        return _mirror(q, axis=1), rel, steps


def _mirror(v: np.ndarray, axis: int = 0) -> np.ndarray:
    """All harmonics -m..m of a real signal from its harmonics a = 0..m along axis."""
    v = np.moveaxis(v, axis, 0)
    return np.moveaxis(np.concatenate([np.conj(v[:0:-1]), v]), 0, axis)


def _times_real(X: np.ndarray, A: np.ndarray) -> np.ndarray:
    """X @ A (..., k) of complex X (..., n) and real A (n, k) by one real matrix product (of
    the real and imaginary parts stacked as rows)."""
    parts = np.concatenate([X.real, X.imag]).reshape(-1, X.shape[-1]) @ A
    half = parts.shape[0] // 2
    return (parts[:half] + 1j * parts[half:]).reshape(X.shape[:-1] + A.shape[1:])
