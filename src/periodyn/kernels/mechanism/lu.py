"""LU factorization with partial pivoting for the constraint Jacobian of an element model,
factored once per configuration and reused for every solve of the transfer-function
derivatives (Schwab & Meijaard 2001, eq. 5-9) and for the constraint forces.

The Jacobian has a few entries per row (an identity row per fixed or dynamic coordinate,
an element's mode gradient per deformation row), so elimination skips zero multipliers
and stops each pivot row at its last nonzero: a chain of elements costs about
``n * band^2`` instead of ``n^3 / 3``, and the solves ``nnz(L + U)`` per right-hand side.
Pivoting is LAPACK's (the largest magnitude in the column), recorded as the row swapped
into place at each step: ``P A = L U`` with unit lower L. The 1-norm condition number is
estimated from the factors (Hager's method, as LAPACK gecon: a few solves, no SVD).
"""

import numpy as np
from numba import njit


@njit(cache=True)
def lu_factor(A, piv):
    """Overwrite A (n, n) with L (strictly lower, unit diagonal implied) and U, piv (n,)
    int64 with the row interchanges. Returns 0, or k + 1 when column k has no nonzero
    pivot (singular matrix)."""
    n = A.shape[0]
    for k in range(n):
        p = k
        big = abs(A[k, k])
        for i in range(k + 1, n):
            if abs(A[i, k]) > big:
                big = abs(A[i, k])
                p = i
        piv[k] = p
        if big == 0.0:
            return k + 1
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
        hi = n
        while hi > k + 1 and A[k, hi - 1] == 0.0:
            hi -= 1
        pivot = A[k, k]
        for i in range(k + 1, n):
            if A[i, k] != 0.0:
                f = A[i, k] / pivot
                A[i, k] = f
                for j in range(k + 1, hi):
                    A[i, j] -= f * A[k, j]
    return 0


@njit(cache=True)
def lu_solve(LU, piv, B):
    """Solve A X = B in place for B (n, k), from :func:`lu_factor` of A."""
    n, k = B.shape
    for i in range(n):
        p = piv[i]
        if p != i:
            for c in range(k):
                B[i, c], B[p, c] = B[p, c], B[i, c]
    for j in range(n):  # L y = P b, column by column of L
        for i in range(j + 1, n):
            f = LU[i, j]
            if f != 0.0:
                for c in range(k):
                    B[i, c] -= f * B[j, c]
    for j in range(n - 1, -1, -1):  # U x = y
        d = LU[j, j]
        for c in range(k):
            B[j, c] /= d
        for i in range(j):
            f = LU[i, j]
            if f != 0.0:
                for c in range(k):
                    B[i, c] -= f * B[j, c]


@njit(cache=True)
def lu_solve_transposed(LU, piv, b):
    """Solve A^T x = b for b (n,) from :func:`lu_factor` of A; returns x (n,)."""
    n = b.shape[0]
    x = b.copy()
    for j in range(n):  # U^T z = b
        s = x[j]
        for i in range(j):
            s -= LU[i, j] * x[i]
        x[j] = s / LU[j, j]
    for j in range(n - 1, -1, -1):  # L^T w = z
        s = x[j]
        for i in range(j + 1, n):
            s -= LU[i, j] * x[i]
        x[j] = s
    for j in range(n - 1, -1, -1):  # x = P^T w
        p = piv[j]
        if p != j:
            x[j], x[p] = x[p], x[j]
    return x


@njit(cache=True)
def lu_solve_transposed_many(LU, piv, B):
    """Solve A^T X = B in place for B (n, k) from :func:`lu_factor` of A, row by row of the
    factors (skipping their zeros): ``nnz(L + U) * k`` operations for a sparse factor."""
    n, k = B.shape
    for j in range(n):  # U^T Y = B: row j of U scatters into the rows below
        d = LU[j, j]
        for c in range(k):
            B[j, c] /= d
        for i in range(j + 1, n):
            u = LU[j, i]
            if u != 0.0:
                for c in range(k):
                    B[i, c] -= u * B[j, c]
    for i in range(n - 1, -1, -1):  # L^T W = Y: row i of L scatters into the rows above
        for j in range(i):
            f = LU[i, j]
            if f != 0.0:
                for c in range(k):
                    B[j, c] -= f * B[i, c]
    for j in range(n - 1, -1, -1):  # X = P^T W
        p = piv[j]
        if p != j:
            for c in range(k):
                B[j, c], B[p, c] = B[p, c], B[j, c]


@njit(cache=True)
def norm1(A):
    """The 1-norm of A (n, n): its largest column sum of magnitudes."""
    return np.max(np.sum(np.abs(A), axis=0))


@njit(cache=True)
def inverse_norm1(LU, piv, max_steps=5):
    """Estimate of ||A^-1||_1 from :func:`lu_factor` of A (Hager 1984): a lower bound,
    exact in most cases, from at most ``max_steps`` pairs of solves with A and A^T."""
    n = LU.shape[0]
    x = np.full(n, 1.0 / n)
    best = 0.0
    last = -1
    for _ in range(max_steps):
        y = x.copy().reshape((n, 1))
        lu_solve(LU, piv, y)
        best = max(best, np.sum(np.abs(y)))
        z = lu_solve_transposed(LU, piv, np.sign(y[:, 0]))
        j = np.argmax(np.abs(z))
        if j == last or np.abs(z[j]) <= np.dot(z, x):
            break
        x[:] = 0.0
        x[j] = 1.0
        last = j
    return best


@njit(cache=True)
def factor(J):
    """(LU, piv) of a copy of J (n, n); a singular J raises (the caller's configuration
    was solved with a regular Jacobian, so this is a model error)."""
    LU = J.copy()
    piv = np.empty(J.shape[0], dtype=np.int64)
    if lu_factor(LU, piv) != 0:
        raise np.linalg.LinAlgError("singular constraint Jacobian: the model is a mechanism at this configuration")
    return LU, piv
