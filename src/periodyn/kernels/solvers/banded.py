"""Banded linear solves for harmonic balance, many right-hand matrices at once.

Input in LAPACK's band format with kl = ku = u: entry (i, j) of the (N, N) matrix,
|i - j| <= u, sits at ``ab[u + i - j, j]`` of ab (2u+1, N). The solver is Gaussian
elimination with partial pivoting restricted to the band (as LAPACK gbsv), working on a
row-wise copy whose rows have room for the fill-in of row interchanges.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def banded_solve(ab, b, x, work):
    """Solve A x = b for a banded complex matrix; returns 0, or k + 1 when the pivot of
    column k is exactly zero (singular matrix).

    ab: (2u+1, N) band storage (above); b, x: (N,); work: (N, 3u+1) scratch holding row i
    of A at work[i, j - i + u] (contiguous rows for the elimination updates; columns up to
    i + 2u for the fill-in of row interchanges)."""
    u = (ab.shape[0] - 1) // 2
    N = ab.shape[1]
    work[:] = 0.0
    for i in range(N):
        for j in range(max(0, i - u), min(N, i + u + 1)):
            work[i, j - i + u] = ab[u + i - j, j]
    x[:] = b
    for k in range(N):
        last = min(N - 1, k + u)
        p = k
        big = abs(work[k, u])
        for i in range(k + 1, last + 1):
            v = abs(work[i, k - i + u])
            if v > big:
                big, p = v, i
        if big == 0.0:
            return k + 1
        right = min(N - 1, k + 2 * u)
        if p != k:
            for j in range(k, right + 1):
                t = work[k, j - k + u]
                work[k, j - k + u] = work[p, j - p + u]
                work[p, j - p + u] = t
            t = x[k]
            x[k] = x[p]
            x[p] = t
        pivot = work[k, u]
        for i in range(k + 1, last + 1):
            factor = work[i, k - i + u] / pivot
            if factor == 0.0:
                continue
            for j in range(k + 1, right + 1):
                work[i, j - i + u] -= factor * work[k, j - k + u]
            x[i] -= factor * x[k]
    for k in range(N - 1, -1, -1):
        s = x[k]
        for j in range(k + 1, min(N - 1, k + 2 * u) + 1):
            s -= work[k, j - k + u] * x[j]
        x[k] = s / work[k, u]
    return 0


@njit(cache=True)
def banded_matvec(ab, x, out):
    """out = A x for A in band storage ab (2u+1, N); x, out (N,)."""
    u = (ab.shape[0] - 1) // 2
    N = ab.shape[1]
    out[:] = 0.0
    for j in range(N):
        for i in range(max(0, j - u), min(N, j + u + 1)):
            out[i] += ab[u + i - j, j] * x[j]


@njit(cache=True)
def banded_solve_batch(ab, b, x, residual, failed):
    """:func:`banded_solve` for S systems: ab (S, 2u+1, N), b and x (S, N); residual (S,)
    gets ||A x - b||; failed (S,) int64 the 1-based singular column or 0."""
    S, rows, N = ab.shape
    work = np.empty((N, rows + (rows - 1) // 2), dtype=np.complex128)
    r = np.empty(N, dtype=np.complex128)
    for s in range(S):
        failed[s] = banded_solve(ab[s], b[s], x[s], work)
        if failed[s]:
            residual[s] = np.nan
            continue
        banded_matvec(ab[s], x[s], r)
        total = 0.0
        for i in range(N):
            d = r[i] - b[s, i]
            total += d.real * d.real + d.imag * d.imag
        residual[s] = np.sqrt(total)
