"""Products with a matrix that has few nonzero entries, for the Magnus kernels
(:mod:`periodyn.kernels.solvers.floquet`).

An orbit's step generator is often sparse: a chain's 80 x 80 generator [[0, I], [K, C]] with
tridiagonal K and diagonal C has about 200 nonzero entries of 6,400, its 6th-order Magnus
generator about 400. A product with such a factor costs (nonzeros x d) multiply-adds instead
of d^3.

* ``sparse_entries``: the nonzero entries (row, column, value) of a square matrix, or -1 when
  there are more than the buffers hold (the caller then multiplies densely).
* ``commutator_entries``: out = X S - S X from S's entries.
* ``matmul_entries``: out = (c S) A from S's entries (c: a scalar factor).
* ``commutator_either``: out = X Y - Y X from the entries of Y, or else of X, when one of
  them is sparse enough.

The entries are kept in row-major order; every sum over them runs in that order, a row of
the dense factor at a time (contiguous).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def sparse_entries(S, rows, cols, vals):
    """Count of the nonzero entries of S (d, d), written in row-major order to rows, cols
    (m,) int64 and vals (m,); -1 when there are more than m."""
    d = S.shape[0]
    m = rows.shape[0]
    count = 0
    for i in range(d):
        for k in range(d):
            v = S[i, k]
            if v != 0.0:
                if count == m:
                    return -1
                rows[count], cols[count], vals[count] = i, k, v
                count += 1
    return count


@njit(cache=True)
def matmul_entries(rows, cols, vals, count, factor, A, out):
    """out = (factor S) A for dense A (d, d) and S given by its ``count`` entries
    (:func:`sparse_entries`): a row of A scaled into a row of out per entry (contiguous,
    vectorised)."""
    d = A.shape[0]
    out[:, :] = 0.0
    for e in range(count):
        i, k, v = rows[e], cols[e], factor * vals[e]
        for c in range(d):
            out[i, c] += v * A[k, c]


@njit(cache=True)
def commutator_entries(X, rows, cols, vals, count, out):
    """out = X S - S X for dense X (d, d) and S given by its ``count`` entries
    (:func:`sparse_entries`); X S as the transpose of S^T X^T (rows, not columns)."""
    d = X.shape[0]
    Xt, XSt = np.ascontiguousarray(X.T), np.empty((d, d))
    matmul_entries(cols, rows, vals, count, 1.0, Xt, XSt)  # S^T X^T
    matmul_entries(rows, cols, vals, count, 1.0, X, out)  # S X
    for i in range(d):
        for j in range(d):
            out[i, j] = XSt[j, i] - out[i, j]


@njit(cache=True)
def commutator_either(X, Y, out, smallest):
    """out = X Y - Y X from the entries of Y, or else of X, when d >= smallest and one of
    them has at most d^2 / 8 nonzero entries; returns whether it did (False: out is
    untouched, the caller multiplies densely)."""
    d = X.shape[0]
    if d < smallest:
        return False
    m = d * d // 8
    rows, cols, vals = np.empty(m, np.int64), np.empty(m, np.int64), np.empty(m)
    count = sparse_entries(Y, rows, cols, vals)
    if count >= 0:
        commutator_entries(X, rows, cols, vals, count, out)
        return True
    count = sparse_entries(X, rows, cols, vals)
    if count < 0:
        return False
    commutator_entries(Y, rows, cols, vals, count, out)  # Y X - X Y
    for i in range(d):
        for j in range(d):
            out[i, j] = -out[i, j]
    return True
