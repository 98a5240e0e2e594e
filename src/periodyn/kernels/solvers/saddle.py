"""Jitted kernels of the stabilized index-1 equations of motion and their variational
equations (``periodyn.numerics.variational``).

Convention (as for every kernel module): float64 arrays, integer loop bounds, no Python
objects, caller-allocated ``out`` arrays filled completely. Leading axis p: a batch of
states. The saddle-point matrix of state k is ``A = [[M, Pq^T], [Pq, 0]]`` (n + m square);
a mass array with a leading axis of 1 is the same constant mass for every state.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def saddle_accelerations(M, f, Pq, phi, phit, gam, qd, a, x_out, Ainv_out):
    """Solve A [q''; lam] = [f; gamma - 2 a (Pq q' + Phi_t) - a^2 Phi] per state.

    M (1 or p, n, n); f, qd (p, n); Pq (p, m, n); phi, phit, gam (p, m); a: Baumgarte
    rate (1/s). Fills x_out (p, n + m) = (q'', lambda) and Ainv_out (p, n + m, n + m)."""
    p, n = f.shape
    m = phi.shape[1]
    A = np.empty((n + m, n + m))
    rhs = np.empty(n + m)
    for k in range(p):
        Mk = M[min(k, M.shape[0] - 1)]
        A[:, :] = 0.0
        A[:n, :n] = Mk
        for i in range(m):
            vel = phit[k, i]
            for j in range(n):
                A[n + i, j] = Pq[k, i, j]
                A[j, n + i] = Pq[k, i, j]
                vel += Pq[k, i, j] * qd[k, j]
            rhs[n + i] = gam[k, i] - 2.0 * a * vel - a * a * phi[k, i]
        rhs[:n] = f[k]
        Ainv_out[k] = np.linalg.inv(A)
        x_out[k] = Ainv_out[k] @ rhs


@njit(cache=True)
def saddle_jacobians(Ainv, Kq, Kv, H, qdd, qd, Pq, dphit, dgam, a, D_out):
    """dq''/dq and dq''/dq' per state from A [dq''; dlam] = [Kq dq + Kv dq'; c_q dq + c_v dq']
    with c_q = dgamma/dq - 2 a ((Pq q')_q + dPhi_t/dq) - a^2 Pq - (Pq q'')_q and
    c_v = dgamma/dq' - 2 a (Pq + dPhi_t/dq').

    Ainv (p, n+m, n+m); Kq, Kv (p, n, n): force Jacobians less (M q'')_q and
    sum lam_k Phi_k,qq; H (p, m, n, n): Phi_k,qq; qdd, qd (p, n); Pq (p, m, n); dphit,
    dgam (p, m, 2n): derivatives of Phi_t and gamma by (q, q'). Fills D_out (p, n, 2n) =
    [dq''/dq, dq''/dq']."""
    p, n = qdd.shape
    m = Pq.shape[1]
    B = np.empty((n + m, 2 * n))
    for k in range(p):
        B[:n, :n] = Kq[k]
        B[:n, n:] = Kv[k]
        for i in range(m):
            for j in range(n):
                ga = 0.0
                gv = 0.0
                for l in range(n):
                    ga += H[k, i, j, l] * qdd[k, l]
                    gv += H[k, i, j, l] * qd[k, l]
                B[n + i, j] = (dgam[k, i, j] - 2.0 * a * (gv + dphit[k, i, j]) - a * a * Pq[k, i, j] - ga)
                B[n + i, n + j] = dgam[k, i, n + j] - 2.0 * a * (Pq[k, i, j] + dphit[k, i, n + j])
        D_out[k] = Ainv[k, :n] @ B
