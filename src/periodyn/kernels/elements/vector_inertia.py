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
    acc = np.zeros((nv, 3))            # g''
    acc_v = np.zeros((nv, 3, n))       # d g'' / d v
    acc_x = np.zeros((nv, 3, n))       # d g'' / d x at fixed v, a
    for i in range(nv):
        for c in range(3):
            _, gi, Hi, Ti = jets.parts(g[i, c])
            G[i, c] = gi
            for a in range(n):
                hv = 0.0
                ha = 0.0
                for b in range(n):
                    hv += Hi[a, b] * ve[b]
                    ha += Hi[a, b] * ae[b]
                    tvv = 0.0
                    for d in range(n):
                        tvv += Ti[a, b, d] * ve[d]
                    acc_x[i, c, a] += tvv * ve[b]
                acc[i, c] += gi[a] * ae[a] + hv * ve[a]
                acc_v[i, c, a] = 2.0 * hv
                acc_x[i, c, a] += ha
    b_i = np.empty(3)
    for i in range(nv):
        for c in range(3):
            b_i[c] = -weights[i] * gravity[c]
        for j in range(nv):
            mij = mass[i, j]
            if mij == 0.0:
                continue
            for c in range(3):
                b_i[c] += mij * acc[j, c]
                for a in range(n):
                    gia = G[i, c, a]
                    if gia == 0.0:
                        continue
                    for b in range(n):
                        M[a, b] += mij * gia * G[j, c, b]
                        C[a, b] += mij * gia * acc_v[j, c, b]
                        K[a, b] += mij * gia * acc_x[j, c, b]
        for c in range(3):
            if b_i[c] == 0.0:
                continue
            _, gi, Hi, _ = jets.parts(g[i, c])
            for a in range(n):
                r[a] += gi[a] * b_i[c]
                for b in range(n):
                    K[a, b] += b_i[c] * Hi[a, b]
