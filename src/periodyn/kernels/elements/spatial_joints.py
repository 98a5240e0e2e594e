"""Spatial families that act on orientation nodes only (Euler parameters, see
:mod:`.rotation`); derivatives by the Taylor jets of :mod:`.jets`.

Euler normalization (one per orientation node): local coordinates ``xe = lam`` (4,),
one mode ``e = lam . lam - 1`` (dimensionless), always rigid; no parameters.

Spatial hinge (SPACAR style) between orientation nodes p and q: local coordinates
``xe = [lam_p (4), lam_q (4)]``; par = [c_p (4), c_q (4)], constant Euler parameters of the
hinge frame relative to each node, chosen so that the two hinge frames ``lam_p * c_p`` and
``lam_q * c_q`` coincide in the reference configuration with their first axis along the
hinge axis. The relative Euler parameters ``r = conj(lam_p * c_p) * (lam_q * c_q)``
(bilinear in xe) give the modes (rad)

- rotation ``e1 = 2 atan2(r1, r0)``: the rotation of q relative to p about the hinge axis,
  continuous for -2 pi < e1 < 2 pi (one full turn either way from the reference); where it
  is constrained, :func:`.constraints.constraints` takes it modulo 2 pi on the branch
  nearest its prescribed value, so a prescribed hinge may turn any number of times;
- misalignments ``e2 = 2 r2``, ``e3 = 2 r3``: small rotations about the hinge frame's second
  and third axes (zero when the relative rotation is about the hinge axis).

Rigid link: a point b carried by a point a and an orientation node o at a fixed offset
(see :func:`rigid_link`); three rigid modes.
"""

import numpy as np
from numba import njit

from . import jets
from .rotation import product

HINGE_ROTATION = 0  # the hinge's rotation mode, an angle defined modulo 2 pi


@njit(cache=True, inline="always")
def store(J, k, n, D, Dx, Dxx, Dxxx):
    """Write the jet J over n coordinates (laid out as :func:`jets.parts`) as mode k: D[k],
    Dx[k, :n], Dxx[k, :n, :n], Dxxx[k, :n, :n, :n]. Inlined, with loops rather than slice
    assignments: a kernel per call site's literal (k, n) and Numba's shape-mismatch message
    code are what a compile would otherwise add."""
    D[k] = J[0]
    o2 = 1 + n
    o3 = o2 + n * n
    for a in range(n):
        Dx[k, a] = J[1 + a]
        for b in range(n):
            Dxx[k, a, b] = J[o2 + a * n + b]
            for c in range(n):
                Dxxx[k, a, b, c] = J[o3 + (a * n + b) * n + c]


@njit(cache=True)
def normalization(xe, par, D, Dx, Dxx, Dxxx):
    """Overwrite mode 0 with ``lam . lam - 1`` and its derivatives w.r.t. lam = xe (4,)."""
    n = 4
    lam = np.empty((4, jets.size(n)))
    for i in range(4):
        jets.seed(xe[i], i, lam[i])
    out = np.empty(jets.size(n))
    tmp = np.empty(jets.size(n))
    jets.constant(-1.0, out)
    for i in range(4):
        jets.mul(lam[i], lam[i], tmp)
        jets.add(out, tmp, out)
    store(out, 0, n, D, Dx, Dxx, Dxxx)


@njit(cache=True)
def relative_coefficients(par):
    """T (4, 4, 4) with ``r_i = sum_jk T[i, j, k] lam_p[j] lam_q[k]`` for the hinge frames
    of par = [c_p, c_q] (8,)."""
    cp_conj = np.empty(4)
    cp_conj[0] = par[0]
    cp_conj[1:] = -par[1:4]
    cq = par[4:8]
    T = np.zeros((4, 4, 4))
    ej = np.zeros(4)
    ek = np.zeros(4)
    a = np.empty(4)
    b = np.empty(4)
    for j in range(4):
        ej[:] = 0.0
        ej[j] = 1.0
        ej[1:] = -ej[1:]  # conj(e_j)
        product(cp_conj, ej, a)  # conj(e_j * c_p) = conj(c_p) conj(e_j)
        for k in range(4):
            ek[:] = 0.0
            ek[k] = 1.0
            product(a, ek, b)
            product(b, cq, T[:, j, k])
    return T


@njit(cache=True)
def hinge(xe, par, D, Dx, Dxx, Dxxx):
    """Overwrite modes (rotation, misalignment_2, misalignment_3) and their derivatives
    w.r.t. xe = [lam_p, lam_q] (8,)."""
    n = 8
    T = relative_coefficients(par)
    r = np.zeros((4, jets.size(n)))
    for i in range(4):
        # bilinear: gradient T lam_q / T^T lam_p, Hessian T in the cross blocks, no third order
        v, g, H, _ = jets.parts(r[i])
        for j in range(4):
            for k in range(4):
                t = T[i, j, k]
                v[0] += t * xe[j] * xe[4 + k]
                g[j] += t * xe[4 + k]
                g[4 + k] += t * xe[j]
                H[j, 4 + k] = t
                H[4 + k, j] = t
    angle = np.empty(jets.size(n))
    jets.atan2(r[1], r[0], angle)
    jets.scale(angle, 2.0, angle)
    store(angle, HINGE_ROTATION, n, D, Dx, Dxx, Dxxx)
    for m in range(2):
        jets.scale(r[2 + m], 2.0, angle)
        store(angle, 1 + m, n, D, Dx, Dxx, Dxxx)


@njit(cache=True)
def rigid_link(xe, par, D, Dx, Dxx, Dxxx):
    """Rigid link of point b to point a and orientation node o: local coordinates
    ``xe = [x_a (3), lam_o (4), x_b (3)]``, par = d (3,) the offset in o's body components;
    modes ``x_b - x_a - R(lam_o) d`` (3, m), zero in the reference."""
    n = 10
    m = jets.size(n)
    R = np.empty((3, 3, m))
    jets.rotation_seeded(xe[3:7], 3, R)
    out = np.empty(m)
    tmp = np.empty(m)
    for i in range(3):
        jets.seed(xe[7 + i], 7 + i, out)
        jets.seed(xe[i], i, tmp)
        jets.sub(out, tmp, out)
        for j in range(3):
            jets.lincomb(1.0, out, -par[j], R[i, j], out)
        store(out, i, n, D, Dx, Dxx, Dxxx)
