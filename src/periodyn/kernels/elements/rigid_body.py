"""Rotational inertia of a rigid body on an orientation node (its translational inertia
is a point mass on its position node, the centre of mass): local coordinates
``xe = lam`` (4,) Euler parameters, ipar = [J (3x3 row-major, kg m^2)], the inertia tensor
about the centre of mass in body components.

Kinetic energy ``T = 1/2 Omega^T J Omega``, ``Omega = 2 G(lam) lam'`` (see :mod:`.rotation`).
With G linear in lam and ``G(a) b = -G(b) a``, Lagrange's equations give the inertia force
``r = 4 G^T J G lam'' + 8 G(lam')^T J G lam'`` (G = G(lam)), mass ``M = 4 G^T J G`` (singular
along lam, the direction the normalization constraint removes) and, with
``Q(w)`` the 4x4 matrix of ``G(a)^T w = Q(w) a``,
``C = dr/dlam' = 8 Q(J G lam') + 8 G(lam')^T J G`` and
``K = dr/dlam = 4 Q(J G lam'') - 4 G^T J G(lam'') - 8 G(lam')^T J G(lam')``.
No gravity (it acts on the centre of mass).
"""

import numpy as np
from numba import njit

from .rotation import g_matrix


@njit(cache=True)
def _q_matrix(w):
    """Q (4,4) with G(a)^T w = Q a for w (3,)."""
    Q = np.empty((4, 4))
    e = np.zeros(4)
    G = np.empty((3, 4))
    for k in range(4):
        e[:] = 0.0
        e[k] = 1.0
        g_matrix(e, G)
        Q[:, k] = G.T @ w
    return Q


@njit(cache=True)
def inertia(xe, ve, ae, ipar, gravity, M, r, C, K):
    """Add the body's rotational inertia to M, r, C, K (4, 4) / (4,) (see module docstring)."""
    J = ipar[:9].reshape((3, 3))
    G = np.empty((3, 4))
    Gv = np.empty((3, 4))
    Ga = np.empty((3, 4))
    lam = xe[:4].copy()
    v = ve[:4].copy()
    a = ae[:4].copy()
    g_matrix(lam, G)
    g_matrix(v, Gv)
    g_matrix(a, Ga)
    JG = J @ G
    w_v = JG @ v
    w_a = JG @ a
    M[:4, :4] += 4.0 * (G.T @ JG)
    r[:4] += 4.0 * (G.T @ w_a) + 8.0 * (Gv.T @ w_v)
    C[:4, :4] += 8.0 * _q_matrix(w_v) + 8.0 * (Gv.T @ JG)
    K[:4, :4] += 4.0 * _q_matrix(w_a) - 4.0 * (G.T @ (J @ Ga)) - 8.0 * (Gv.T @ (J @ Gv))
