"""Inertia of interpolated vectors: the common inertia kernel of the spatial families.

Many spatial inertias are kinetic energies of vectors that are functions of the local
coordinates, ``T = 1/2 sum_ij m_ij g_i' . g_j'``: the Hermite centre line of a beam
(positions and scaled end tangents), and the rotary inertia of a frame R with second
moments of mass E_k about its axes t_k = R a_k (``1/2 tr(R' E R'^T)`` = ``1/2 w^T J w``,
J = tr(E) I - E). Lagrange's equations of such an energy give the virtual-power force
``r = sum_i G_i^T b_i``, ``b_i = sum_j m_ij g_j'' - w_i gravity``, with
``g'' = G a + Hg[v, v]`` (G, Hg, Tg the first to third derivatives of g), and

    M = sum m_ij G_i^T G_j,     C = d r / d v = sum m_ij G_i^T 2 Hg_j v,
    K = d r / d x = sum_i Hg_i . b_i + sum m_ij G_i^T (Hg_j a + Tg_j[v, v]),

exact for whatever coordinates the vectors depend on (Euler parameters included: off
their normalization the energy is still a function of the coordinates, and on it equals
the rigid-body energy).
"""

import numpy as np
from numba import njit

from . import jets


@njit(cache=True)
def add_vector_inertia(g, mass, weights, ve, ae, gravity, M, r, C, K):
    """Add the inertia of the vectors g (nv, 3, jets.size(n)) (jets over the n local
    coordinates) with mass coefficients mass (nv, nv) (kg, kg m, kg m^2 by the vectors'
    units) and gravity weights (nv,) (kg; gravity (3,) m/s^2) to M (n,n), r (n,),
    C (n,n), K (n,n) at velocities ve (n,) and accelerations ae (n,)."""
    nv = g.shape[0]
    n = jets.dim(g[0, 0])
    G = np.empty((nv, 3, n))
    acc = np.empty((nv, 3))            # g''
    acc_v = np.empty((nv, 3, n))       # d g'' / d v
    acc_x = np.empty((nv, 3, n))       # d g'' / d x at fixed v, a
    for i in range(nv):
        for c in range(3):
            _, gi, Hi, Ti = jets.parts(g[i, c])
            G[i, c] = gi
            Hv = Hi @ ve
            acc[i, c] = gi @ ae + Hv @ ve
            acc_v[i, c] = 2.0 * Hv
            acc_x[i, c] = Hi @ ae
            for b in range(n):
                acc_x[i, c, b] += (Ti[b] @ ve) @ ve
    for i in range(nv):
        b_i = -weights[i] * gravity
        Y = np.zeros((3, n))     # sum_j m_ij G_j
        Yv = np.zeros((3, n))    # sum_j m_ij d g_j'' / d v
        Yx = np.zeros((3, n))    # sum_j m_ij d g_j'' / d x
        for j in range(nv):
            mij = mass[i, j]
            if mij == 0.0:
                continue
            b_i = b_i + mij * acc[j]
            Y += mij * G[j]
            Yv += mij * acc_v[j]
            Yx += mij * acc_x[j]
        Gi = G[i]
        M += Gi.T @ Y
        C += Gi.T @ Yv
        K += Gi.T @ Yx
        r += Gi.T @ b_i
        for c in range(3):
            if b_i[c] != 0.0:
                K += b_i[c] * jets.parts(g[i, c])[2]
