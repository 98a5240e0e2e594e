"""Jitted assembly of the phase-time right-hand side of an ODE with constant mass and its
variational columns (``periodyn.numerics.variational.flow``, lean path): the force and
its Jacobians come from the model (Python callables), everything after them is one call.

Convention (as for every kernel module): float64 arrays, integer loop bounds,
caller-allocated ``out`` filled completely. The state vector y holds b members:
y[:b 2n] the states (q, q') row by row, y[b 2n:] the variational columns (b, 2n, kc),
kc = k start directions plus one parameter-sensitivity column when ``sens``.
Minv is M^-1 (n, n), or (0, 0) for a unit mass. With x = (q', M^-1 f) the state
derivative in time, the phase-time derivative is x / omega; column j advances by
(C_j', M^-1 (Kq C_j + Kv C_j')) / omega; the sensitivity column adds
(-x / omega * scaling + (0, M^-1 df)) / omega, where ``scaling`` is 1 for p = omega
(time scales with 1/omega) and 0 for a named parameter, and df is df/dp at fixed phase.
"""

from __future__ import annotations

from numba import njit


@njit(cache=True)
def _apply_inverse_mass(Minv, x, out, scale):
    """out[r] = scale (Minv x)[r] (x itself when Minv is (0, 0): unit mass)."""
    n = x.shape[0]
    if Minv.shape[0] == 0:
        for r in range(n):
            out[r] = scale * x[r]
        return
    for r in range(n):
        v = 0.0
        for c in range(n):
            v += Minv[r, c] * x[c]
        out[r] = scale * v


@njit(cache=True)
def ode_variational_rhs(y, f, Kq, Kv, df, Minv, omega, kc, sens, scaling, work, out):
    """Fill out (like y) from y, the forces f (b, n), Kq = df/dq and Kv = df/dq' (b, n, n)
    (unused without columns), df (b, n) (used when sens), Minv (n, n) or (0, 0) for a
    unit mass; work: scratch of n (kc + 2) floats."""
    b, n = f.shape
    N = 2 * n
    bN = b * N
    inv = 1.0 / omega
    acc = work[:n * kc].reshape(n, kc)
    col = work[n * kc:n * kc + n]
    res = work[n * kc + n:n * kc + 2 * n]
    for i in range(b):
        s = i * N
        for r in range(n):
            out[s + r] = y[s + n + r] * inv
        _apply_inverse_mass(Minv, f[i], res, inv)
        out[s + n:s + N] = res
        if kc == 0:
            continue
        base = bN + s * kc  # member i's columns: (2n, kc) row by row
        C = y[base:base + N * kc].reshape(N, kc)
        O = out[base:base + N * kc].reshape(N, kc)
        acc[:, :] = 0.0
        for r in range(n):  # Kq C_q + Kv C_v, the column index innermost (contiguous)
            for c in range(n):
                kq, kv = Kq[i, r, c], Kv[i, r, c]
                for j in range(kc):
                    acc[r, j] += kq * C[c, j] + kv * C[n + c, j]
        for r in range(n):
            for j in range(kc):
                O[r, j] = C[n + r, j] * inv
        for j in range(kc):
            for r in range(n):
                col[r] = acc[r, j]
            _apply_inverse_mass(Minv, col, res, inv)
            for r in range(n):
                O[n + r, j] = res[r]
        if sens:
            j = kc - 1
            for r in range(N):  # the scaling part: -x / omega (x = the state derivative in time)
                O[r, j] -= scaling * out[s + r] * inv
            _apply_inverse_mass(Minv, df[i], res, inv)
            for r in range(n):
                O[n + r, j] += res[r]
