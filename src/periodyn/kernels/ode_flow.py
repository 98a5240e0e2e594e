"""Jitted assembly of the phase-time right-hand side of an ODE with constant mass and its
variational columns (``periodyn.nonlinear.variational.flow``, lean path): the force and
its Jacobians come from the model (Python callables), everything after them is one call.

Convention (as for every kernel module): float64 arrays, integer loop bounds,
caller-allocated ``out`` filled completely. The state vector y holds b members:
y[:b 2n] the states (q, q') row by row, y[b 2n:] the variational columns (b, 2n, kc),
kc = k start directions plus one parameter-sensitivity column when ``sens``.
Minv is M^-1 (n, n) (the identity for a unit mass). With x = (q', M^-1 f) the state
derivative in time, the phase-time derivative is x / omega; column j advances by
(C_j', M^-1 (Kq C_j + Kv C_j')) / omega; the sensitivity column adds
(-x / omega * scaling + (0, M^-1 df)) / omega, where ``scaling`` is 1 for p = omega
(time scales with 1/omega) and 0 for a named parameter, and df is df/dp at fixed phase.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def ode_variational_rhs(y, f, Kq, Kv, df, Minv, omega, kc, sens, scaling, out):
    """Fill out (like y) from y, the forces f (b, n), Kq = df/dq and Kv = df/dq' (b, n, n)
    (unused without columns), df (b, n) (used when sens), Minv (n, n)."""
    b, n = f.shape
    N = 2 * n
    bN = b * N
    inv = 1.0 / omega
    acc = np.empty(n)
    for i in range(b):
        s = i * N
        for r in range(n):
            x = 0.0
            for c in range(n):
                x += Minv[r, c] * f[i, c]
            acc[r] = x
            out[s + r] = y[s + n + r] * inv
            out[s + n + r] = x * inv
        if kc == 0:
            continue
        base = bN + s * kc  # member i's columns: rows 0..2n-1, kc entries each
        for j in range(kc):
            for r in range(n):
                out[base + r * kc + j] = y[base + (n + r) * kc + j] * inv
            for r in range(n):
                x = 0.0
                for c in range(n):
                    x += Kq[i, r, c] * y[base + c * kc + j] + Kv[i, r, c] * y[base + (n + c) * kc + j]
                acc[r] = x
            for r in range(n):
                x = 0.0
                for c in range(n):
                    x += Minv[r, c] * acc[c]
                out[base + (n + r) * kc + j] = x * inv
        if sens:
            j = kc - 1
            for r in range(N):  # the scaling part: -x / omega (x = the state derivative in time)
                out[base + r * kc + j] -= scaling * out[s + r] * inv
            for r in range(n):
                x = 0.0
                for c in range(n):
                    x += Minv[r, c] * df[i, c]
                out[base + (n + r) * kc + j] += x * inv
