"""Layout of harmonic block matrices: the block-banded pattern and the real basis.

A vector of harmonics is harmonic-major, ``x[(l + m) n + i]`` for l = -m..m and
coordinate i, size N = (2m+1) n. A block matrix of the Hill/HB operator couples
harmonics k and l through an (n, n) block when |k - l| <= band (the highest coefficient
harmonic kept); :class:`BlockPattern` stores the blocks as data (nb, n, n) and places
them in CSC, LAPACK band or dense storage. For a real system the operator satisfies
``A = J conj(A) J`` (J: l -> -l), so the unitary change of basis of :func:`real_form`
makes it real (LAPACK's real solvers are about three times faster than complex ones).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property, lru_cache

import numpy as np
import scipy.sparse as sp

__all__ = ["BlockPattern", "block_pattern", "real_form", "to_real_basis", "from_real_basis"]


@dataclass(frozen=True)
class BlockPattern:
    """Sparsity of a (2m+1)n block matrix with blocks (k, l) for |k - l| <= band.

    k_index, l_index: (nb,) harmonic indices of block rows/columns; half_bandwidth
    u = (band + 1) n - 1. Built on first use (O(nb n^2) entries): csc_perm maps the
    flattened (nb, n, n) block data to CSC data order; indices/indptr are the CSC arrays;
    band_rows/band_cols place the flattened block data in LAPACK band storage
    ab[u + i - j, j].
    """

    m: int
    n: int
    band: int
    k_index: np.ndarray = field(compare=False)
    l_index: np.ndarray = field(compare=False)
    half_bandwidth: int

    @cached_property
    def _entries(self) -> tuple[np.ndarray, np.ndarray]:
        """Row and column (each (nb n^2,)) of every entry of the flattened block data."""
        m, n = self.m, self.n
        i_loc, j_loc = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
        rows = ((self.k_index + m)[:, None, None] * n + i_loc[None]).reshape(-1)
        cols = ((self.l_index + m)[:, None, None] * n + j_loc[None]).reshape(-1)
        return rows, cols

    @cached_property
    def _csc(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        rows, cols = self._entries
        order = np.lexsort((rows, cols))
        indptr = np.zeros(self.size + 1, dtype=np.int64)
        np.add.at(indptr, cols + 1, 1)
        return order, rows[order].astype(np.int32), np.cumsum(indptr).astype(np.int32)

    @property
    def csc_perm(self) -> np.ndarray:
        return self._csc[0]

    @property
    def indices(self) -> np.ndarray:
        return self._csc[1]

    @property
    def indptr(self) -> np.ndarray:
        return self._csc[2]

    @cached_property
    def band_rows(self) -> np.ndarray:
        rows, cols = self._entries
        return self.half_bandwidth + rows - cols

    @property
    def band_cols(self) -> np.ndarray:
        return self._entries[1]

    @property
    def size(self) -> int:
        return (2 * self.m + 1) * self.n

    @property
    def centre_block(self) -> int:
        """Index of the block (k, l) = (0, 0), the mean system's."""
        return int(np.flatnonzero((self.k_index == 0) & (self.l_index == 0))[0])

    @property
    def narrow(self) -> bool:
        """The band holds less than about half of the matrix (4u < size)."""
        return 4 * self.half_bandwidth < self.size

    def dense(self, blocks: np.ndarray) -> np.ndarray:
        """Dense (size, size) complex array of the block data (nb, n, n)."""
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
    return BlockPattern(m, n, band, ks[keep], ls[keep], (band + 1) * n - 1)


def real_form(A: np.ndarray, m: int, n: int, halves: int = 2) -> np.ndarray:
    """Unitary map of a Hill matrix of a real system to a real matrix.

    A (halves N, halves N), N = (2m+1)n, harmonic-major blocks in each half (halves=2:
    the first-order matrix on [x; lambda x], halves=1: the HB matrix), satisfies
    A = J conj(A) J, J the reversal of harmonic index l -> -l; with Q = [e_0,
    (e_l + e_-l)/sqrt2, i(e_l - e_-l)/sqrt2] (l > 0), Q^H A Q is real."""
    zero, pos, neg = _real_form_indices(m, n, halves)
    r2 = np.sqrt(0.5)
    AQ = np.concatenate([A[:, zero], r2 * (A[:, pos] + A[:, neg]), 1j * r2 * (A[:, pos] - A[:, neg])], axis=1)
    return to_real_basis(AQ, m, n, halves)


def to_real_basis(v: np.ndarray, m: int, n: int, halves: int = 2) -> np.ndarray:
    """Q^H v along the first axis (see :func:`real_form`), real part; v (halves N, ...)."""
    zero, pos, neg = _real_form_indices(m, n, halves)
    r2 = np.sqrt(0.5)
    return np.concatenate([v[zero], r2 * (v[pos] + v[neg]), -1j * r2 * (v[pos] - v[neg])], axis=0).real


def from_real_basis(Wv: np.ndarray, m: int, n: int, halves: int = 2) -> np.ndarray:
    """Q Wv along the second-to-last axis: real-basis vectors (..., halves N, k) back in
    the harmonic basis, complex."""
    zero, pos, neg = _real_form_indices(m, n, halves)
    r2 = np.sqrt(0.5)
    Z = np.empty(Wv.shape, dtype=complex)
    nz, npos = zero.size, pos.size
    Z[..., zero, :] = Wv[..., :nz, :]
    plus, minus = Wv[..., nz: nz + npos, :], Wv[..., nz + npos:, :]
    Z[..., pos, :] = r2 * (plus + 1j * minus)
    Z[..., neg, :] = r2 * (plus - 1j * minus)
    return Z


@lru_cache(maxsize=64)
def _real_form_indices(m: int, n: int, halves: int = 2) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows of a Hill vector (halves blocks of (2m+1)n, harmonic-major) with l = 0, l > 0,
    and the partner row (-l, same coordinate, same half) of each l > 0 row."""
    N = (2 * m + 1) * n
    rows = np.arange(halves * N)
    half, rem = np.divmod(rows, N)
    block, coord = np.divmod(rem, n)
    l = block - m
    pos = rows[l > 0]
    partner = half[pos] * N + (m - l[pos]) * n + coord[pos]
    return rows[l == 0], pos, partner
