"""Constitutive forces of deformation modes, for any element family.

Flexible and free modes carry a linear Kelvin-Voigt law ``sigma = S e + S_d e' + sigma_0``
(S, S_d (nm, nm), a constant stress sigma_0 (nm,) such as a resisting torque on a hinge;
rows/columns/entries of rigid and prescribed modes are zero, their forces are reactions). The nodal force is ``f = -D_x^T sigma``; this kernel adds
``-f`` to r and its derivatives to C (velocity) and K (position, at fixed velocity).
"""

import numpy as np
from numba import njit


@njit(cache=True)
def add_elastic(nm, nx, D, Dx, Dxx, ve, S, Sd, s0, r, C, K):
    """D (>=nm,), Dx (>=nm, >=nx), Dxx (>=nm, >=nx, >=nx) local deformation tensors,
    ve (nx,) local velocities, s0 (>=nm,) constant stresses; adds into r (nx,), C (nx,nx),
    K (nx,nx)."""
    rate = np.zeros(nm)          # e'
    rate_x = np.zeros((nm, nx))  # d e' / d x at fixed velocity
    for k in range(nm):
        for a in range(nx):
            rate[k] += Dx[k, a] * ve[a]
            for c in range(nx):
                rate_x[k, a] += Dxx[k, a, c] * ve[c]
    for m in range(nm):
        sigma = s0[m]
        for k in range(nm):
            sigma += S[m, k] * D[k] + Sd[m, k] * rate[k]
        for a in range(nx):
            r[a] += Dx[m, a] * sigma
            for b in range(nx):
                K[a, b] += sigma * Dxx[m, a, b]
        for k in range(nm):
            smk = S[m, k]
            dmk = Sd[m, k]
            if smk == 0.0 and dmk == 0.0:
                continue
            for a in range(nx):
                for b in range(nx):
                    C[a, b] += Dx[m, a] * dmk * Dx[k, b]
                    K[a, b] += Dx[m, a] * (smk * Dx[k, b] + dmk * rate_x[k, b])
