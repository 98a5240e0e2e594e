"""The mean system of a model in its undamped modes, for the HB truncation indicator
(:mod:`periodyn.harmonic.truncation`): bounds and solves of the mean-system equations
D x = R, D = sum_t coef_t Xbar_t (Xbar_t the mean blocks of the Q coefficient terms M, C_p,
K_p, coef_t complex weights per equation).

In the basis Phi of the undamped modes of the symmetric parts of the mean K_0 and M,
D = Phi^-T (Dg + E) Phi^-1 with Dg diagonal. With column weights v_i = max_a |Phi_ai| and
rho = max_j sum_i v_i |E_ij| / (|Dg_i| v_j) < 1,

    |D^-1 R|_max <= sum_i v_i |(Phi^T R)_i / Dg_i| / (1 - rho)      (O(Q n^2) per R),

and the Jacobi iteration y <- y + Dg^-1 (Phi^T R - (Dg + E) y) converges to D^-1 R = Phi y
(4-5 steps of 4 Q n^2 flops to MODAL_RTOL at 128 rod elements, against the complex LU's 8/3 n^3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

__all__ = ["MeanModalSystem", "MODAL_RTOL", "MODAL_STEPS", "BLOCK"]

#: the Jacobi iteration stops where a step changes the weighted 1-norm sum_i v_i |y_i| (a
#: bound of |Phi y|_max) by at most this of itself (the solution then agrees with the LU
#: solve to 1e-14), or gives up (NaN) after MODAL_STEPS steps
MODAL_RTOL = 1e-14
MODAL_STEPS = 40
#: equations (or speeds) per matrix product, the last block padded with zeros: at a fixed width
#: every column goes through the same BLAS kernel, so an equation's rounding does not depend on
#: its place or its neighbours (with a varying width the edge kernels differ)
BLOCK = 16


@dataclass(frozen=True, eq=False)
class MeanModalSystem:
    """phi (n, n) the undamped modes, weights (n,) max_a |Phi_ai|, diagonal (Q, n) of
    Phi^T Xbar_t Phi, off (n, Q n) their off-diagonal moduli stacked, projected (Q n, n) the
    blocks Phi^T Xbar_t Phi stacked."""

    phi: np.ndarray
    weights: np.ndarray
    diagonal: np.ndarray
    off: np.ndarray
    projected: np.ndarray

    @classmethod
    def of(cls, mean: list[np.ndarray], Pc: int) -> "MeanModalSystem | None":
        """The modal data of the mean blocks [M, C_p.., K_p..] (each (n, n)); None where the
        mean mass is not positive definite or a mean is complex (not the means of real samples)."""
        if any(np.iscomplexobj(X) and X.imag.any() for X in mean):
            return None
        mean = [X.real for X in mean]
        M, K0 = mean[0], mean[1 + Pc]
        try:
            phi = scipy.linalg.eigh(0.5 * (K0 + K0.T), 0.5 * (M + M.T))[1]
        except (np.linalg.LinAlgError, ValueError):
            return None
        projected = np.stack([phi.T @ X @ phi for X in mean])  # (Q, n, n)
        diagonal = np.diagonal(projected, axis1=1, axis2=2).copy()
        off = np.abs(projected)
        off[:, np.arange(phi.shape[0]), np.arange(phi.shape[0])] = 0.0
        weights = np.abs(phi).max(axis=0)
        if not (np.isfinite(projected).all() and (weights > 0).all()):
            return None
        return cls(phi, weights, diagonal, np.ascontiguousarray(off.transpose(1, 0, 2).reshape(phi.shape[0], -1)),
                   np.ascontiguousarray(projected.reshape(-1, phi.shape[0])))

    def bounds(self, coef: np.ndarray, R: np.ndarray) -> np.ndarray:
        """Upper bounds (V,) of |D^-1 R|_max for weights coef (V, Q) and right sides R (V, n):
        inf where rho >= 1 or not finite."""
        V = R.shape[0]
        proj = np.concatenate([R.real, R.imag]) @ self.phi  # Phi^T R by one real product, (2V, n)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            Dg = coef @ self.diagonal  # (V, n)
            coupling = ((self.weights / np.abs(Dg)) @ self.off).reshape(V, coef.shape[1], -1)  # (V, Q, n)
            rho = (np.abs(coef)[..., None] * coupling / self.weights).sum(axis=1).max(axis=1, initial=0.0)
            b = (self.weights * np.abs((proj[:V] + 1j * proj[V:]) / Dg)).sum(axis=1) / (1.0 - rho)
        return np.where((rho < 1.0) & np.isfinite(b), b, np.inf)

    def solve_moduli(self, coef: np.ndarray, R: np.ndarray) -> np.ndarray:
        """|D^-1 R| (V, n) for weights coef (V, Q) and right sides R (V, n) by the Jacobi
        iteration, NaN where it did not reach MODAL_RTOL in MODAL_STEPS steps. Each equation iterates on
        its own (a converged one is left alone) and every product runs on blocks of BLOCK
        equations (one shape): an equation's solution does not depend on the others to the bit."""
        V, n = R.shape
        blocks = -(-V // BLOCK)
        weights = np.zeros((blocks * BLOCK, coef.shape[1]), complex)
        weights[:V] = coef
        Dg = weights @ self.diagonal  # (V padded, n)
        Dg[V:] = 1.0
        b = np.zeros((blocks * BLOCK, n), complex)
        b[:V] = R
        b = _blockwise(b, self.phi)  # Phi^T R
        y = b / Dg
        active = np.arange(blocks * BLOCK) < V
        for _ in range(MODAL_STEPS):
            rows = np.flatnonzero(np.repeat(active.reshape(blocks, BLOCK).any(axis=1), BLOCK))
            Z = _blockwise(y[rows], self.projected.T).reshape(rows.size, -1, n)  # per term, (r, Q, n)
            dy = (b[rows] - np.einsum("vq,vqn->vn", weights[rows], Z)) / Dg[rows]
            go = active[rows]
            y[rows[go]] += dy[go]
            size = np.abs(y[rows[go]]) @ self.weights
            active[rows[go]] = (np.abs(dy[go]) @ self.weights > MODAL_RTOL * size) | ~np.isfinite(size)
            if not active.any():
                break
        out = np.abs(_blockwise(y, self.phi.T)[:V])
        out[active[:V]] = np.nan
        return out


def _blockwise(X: np.ndarray, A: np.ndarray) -> np.ndarray:
    """X @ A (V, c) of complex X (V, r) (V a multiple of BLOCK) and real A (r, c): per block of
    BLOCK rows one real product of the real and imaginary parts stacked (one shape for every
    block, so a row's rounding does not depend on V)."""
    B = X.reshape(-1, BLOCK, X.shape[1])
    P = np.matmul(np.concatenate([B.real, B.imag], axis=1), A)  # (V / BLOCK, 2 BLOCK, c)
    return (P[:, :BLOCK] + 1j * P[:, BLOCK:]).reshape(X.shape[0], A.shape[1])
