"""The IHB Newton Jacobian on a fixed sparsity pattern: built once, filled per Newton step.

The Jacobian of the harmonic-balance residual (``periodyn.nonlinear.ihb_solver``) is a sparse matrix of
(2H+1)x(2H+1) blocks, one per pair of coordinates (or coordinate and multiplier) whose sampled
derivative matrices are non-zero somewhere on the orbit:

    J_qq[i, j] = G(K_ij) + G(C_ij) D + G(M_ij) D^2,    J_q,lam[j, k] = J_lam,q[k, j] = G(Phi_q,kj)

with G the product blocks of ``periodyn.nonlinear.ihb_fourier`` and D = Omega d/dtau in the real layout.
G(A)[k, l] (k, l the harmonic numbers of row and column) is made of A_(k-l) and A_(k+l), so a
sampled entry whose spectrum is negligible beyond harmonic r (|A_d| <= 1e-13 max|A| for d > r,
its *reach*) has a block inside the band |k - l| <= r. A constant entry has G = c I exactly: its
block is c I, with c D (band 0: a_k <-> b_k) for a damping entry and the diagonal c D^2 for a
mass entry. So every block is a band of the harmonic numbers, reach -1 (diagonal) to 2H (dense).

Pattern: the first evaluation fixes the block pairs and their reach; later evaluations only fill
data, and the pattern is rebuilt (only ever larger, a new reach with a margin of 4 harmonics)
when an evaluation needs a pair or a reach outside it (checked every time). The values dropped
outside the band are below 1e-13 of their entry's largest harmonic: Newton's steps are those of
the exact Jacobian to that accuracy, and the residual, hence every converged orbit, is exact.
With the pattern come the CSC index arrays (data gathered from the blocks in CSC order, no COO
conversion) and one fill-reducing symmetric ordering per pattern: reverse Cuthill-McKee with
SuperLU in natural order (a narrow band for chain-like mechanisms), unless SuperLU's own COLAMD
gives less fill on the first matrix.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import reverse_cuthill_mckee

from ..numerics.spectra import fourier_coefficients
from .ihb_fourier import spectrum_blocks

__all__ = ["entry_classes", "JacobianPattern", "FillOrdering", "block_needs"]

_DROP = 1e-13  # spectrum values below this fraction of an entry's largest are outside its reach
_MARGIN = 4  # extra reach given when a pattern is rebuilt


def entry_classes(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(varying, nonzero) boolean (a, b) of samples A (p, a, b): an entry varies when some
    sample differs from the first; broadcast (stride-0) samples are constant."""
    nz0 = A[0] != 0
    if A.shape[0] == 1 or A.strides[0] == 0:
        return np.zeros_like(nz0), nz0
    var = np.any(A != A[0], axis=0)
    return var, var | nz0


class FillOrdering:
    """Fill-reducing symmetric permutation of one sparsity pattern, reused for every matrix
    with that pattern: ``factor(J) -> solve(b)``.

    rows, cols: (nnz,) positions of ``J.data`` (CSC order) in the unpermuted matrix;
    method: "rcm" (reverse Cuthill-McKee, SuperLU in natural order), "colamd" (SuperLU's
    own), or None to choose at the first factorization by the fill of both (a rebuilt,
    larger pattern keeps the choice: :attr:`method` is set then).
    """

    def __init__(self, size: int, rows: np.ndarray, cols: np.ndarray, method: str | None = None):
        self.size, self.rows, self.cols, self.method = size, rows, cols, method
        self._plan = None

    def _rcm_plan(self):
        if self._plan is None:
            pattern = sp.csr_matrix((np.ones(len(self.rows)), (self.rows, self.cols)), shape=(self.size,) * 2)
            perm = reverse_cuthill_mckee((pattern + pattern.T).tocsr(), symmetric_mode=True)
            pos = np.empty(self.size, dtype=np.int64)
            pos[perm] = np.arange(self.size)
            r, c = pos[self.rows], pos[self.cols]
            order = np.lexsort((r, c))
            indptr = np.concatenate([[0], np.cumsum(np.bincount(c, minlength=self.size))])
            self._plan = (perm, order, r[order], indptr)
        return self._plan

    def _rcm(self, J):
        perm, order, indices, indptr = self._rcm_plan()
        lu = spla.splu(sp.csc_matrix((J.data[order], indices, indptr), shape=J.shape), permc_spec="NATURAL")
        return lu, _solver(lu, perm)

    def factor(self, J) -> Callable:
        if self.method == "colamd":
            return spla.splu(J).solve
        lu, solve = self._rcm(J)
        if self.method is None:  # decide once: RCM + natural order vs COLAMD, by fill
            lu_col = spla.splu(J)
            self.method = "rcm" if lu.L.nnz + lu.U.nnz <= lu_col.L.nnz + lu_col.U.nnz else "colamd"
            return solve if self.method == "rcm" else lu_col.solve
        return solve


def _solver(lu, perm) -> Callable:
    def solve(b):
        x = np.empty_like(b, dtype=float)
        x[perm] = lu.solve(np.ascontiguousarray(b[perm], dtype=float))
        return x
    return solve


def block_needs(Kt, Ct, M, Pq, H: int):
    """What the Jacobian blocks need from samples Kt, Ct, M (p, n, n), Pq (p, m, n).

    Returns (need, varying, constants, spectra): need (n+m, n+m) int reach of each block
    pair (-2 for no block); varying: list of (part, rows, cols) of the entries that vary
    along the orbit, part in "KCMP"; constants: list of (part, rows, cols, values) of the
    non-zero constant ones; spectra (E, 4H+1) of the varying entries (index d + 2H), in order.
    """
    n, m = Kt.shape[1], Pq.shape[1]
    need = np.full((n + m, n + m), -2, dtype=np.int64)
    varying, constants, cols = [], [], []
    for part, A in (("K", Kt), ("C", Ct), ("M", M), ("P", Pq)):
        var, nz = entry_classes(A)
        I, J = np.nonzero(nz & ~var)
        constants.append((part, I, J, A[0, I, J]))
        const = 0 if part == "C" else -1  # c D couples a_k with b_k; c I and c D^2 are diagonal
        if part == "P":
            I, J = J, n + I
            np.maximum.at(need, (J, I), const)
        np.maximum.at(need, (I, J), const)
        I, J = np.nonzero(var)
        varying.append((part, I, J))
        cols.append(A[:, I, J])
    S = np.concatenate(cols, axis=1)
    spectra = fourier_coefficients(S, 2 * H).T if S.shape[1] else np.zeros((0, 4 * H + 1), complex)
    mag = np.abs(spectra[:, 2 * H:])  # |A_d|, d = 0..2H (|A_-d| = |A_d|)
    big = mag > _DROP * mag.max(axis=1, initial=0.0)[:, None]
    reach = 2 * H - np.argmax(big[:, ::-1], axis=1)
    e = 0
    for part, I, J in varying:
        r = reach[e:e + len(I)]
        e += len(I)
        if part == "P":
            np.maximum.at(need, (J, n + I), r)
            np.maximum.at(need, (n + I, J), r)
        else:
            np.maximum.at(need, (I, J), r)
    return need, varying, constants, spectra


def _harmonic_numbers(H: int) -> np.ndarray:
    k = np.arange(1, H + 1)
    return np.concatenate([[0], k, k])


class JacobianPattern:
    """Block pattern of the IHB Jacobian (see module docstring).

    H harmonics, n coordinates, m multipliers; reach (n+m, n+m) int: -2 no block, -1
    diagonal block, r >= 0 the band |k - l| <= r of harmonic numbers; ordering: the
    :class:`FillOrdering` method (None: choose at the first factorization).
    """

    def __init__(self, H: int, n: int, m: int, reach: np.ndarray, ordering: str | None = None):
        self.H, self.n, self.m, self.L = H, n, m, 2 * H + 1
        self.reach = reach
        L = self.L
        self.bi, self.bj = np.nonzero(reach >= -1)
        self.slot = np.full(reach.shape, -1, dtype=np.int64)
        self.slot[self.bi, self.bj] = np.arange(len(self.bi))
        h = _harmonic_numbers(H)
        band = np.abs(h[:, None] - h[None, :])
        ar = np.arange(L)
        inside = (band[None] <= reach[self.bi, self.bj][:, None, None]) | (ar[:, None] == ar[None, :])[None]
        b, r, c = np.nonzero(inside)
        rows = self.bi[b] * L + r
        cols = self.bj[b] * L + c
        self.size = (n + m) * L
        order = np.lexsort((rows, cols))
        self.gather = (b * L * L + r * L + c)[order]
        self.indices = rows[order]
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(cols, minlength=self.size))])
        self.ordering = FillOrdering(self.size, rows[order], cols[order], ordering)

    def fits(self, need: np.ndarray) -> bool:
        return bool(np.all(need <= self.reach))

    def widened(self, need: np.ndarray) -> np.ndarray:
        """Reach covering this pattern and ``need`` (a new reach gets a margin)."""
        grow = need > self.reach
        return np.where(grow & (need >= 0), np.minimum(need + _MARGIN, 2 * self.H),
                        np.where(grow, need, self.reach))

    def assemble(self, Om: float, varying, constants, spectra):
        """The Jacobian (csc, carrying ``fill_ordering``) at base frequency Om (rad/s) from the
        entries of the sampled matrices (:func:`block_needs`)."""
        H, L, n = self.H, self.L, self.n
        k = np.arange(1, H + 1)
        d2 = np.concatenate([[0.0], -(Om * k) ** 2, -(Om * k) ** 2])  # diagonal of (Om D)^2
        G = spectrum_blocks(spectra, H)
        B = np.zeros((len(self.bi), L, L))
        e = 0
        for part, I, J in varying:
            g = G[e:e + len(I)]
            e += len(I)
            if part == "K":
                B[self.slot[I, J]] += g
            elif part == "C":  # G @ (Om D), column by column
                s = self.slot[I, J]
                B[s, :, H + 1:] += Om * k * g[:, :, 1:H + 1]
                B[s, :, 1:H + 1] -= Om * k * g[:, :, H + 1:]
            elif part == "M":
                B[self.slot[I, J]] += g * d2
            else:
                B[self.slot[J, n + I]] += g
                B[self.slot[n + I, J]] += g
        ar = np.arange(L)
        for part, I, J, c in constants:
            if part == "C":
                s = self.slot[I, J][:, None]
                B[s, k, H + k] += (Om * c)[:, None] * k
                B[s, H + k, k] -= (Om * c)[:, None] * k
                continue
            diag = c[:, None] * (d2 if part == "M" else np.ones(L))
            if part == "P":
                B[self.slot[J, n + I][:, None], ar, ar] += diag
                I, J = n + I, J
            B[self.slot[I, J][:, None], ar, ar] += diag
        Jac = sp.csc_matrix((B.ravel()[self.gather], self.indices, self.indptr), shape=(self.size, self.size))
        Jac.fill_ordering = self.ordering
        return Jac
