"""Spatial beam element (SPACAR-style, Euler-Bernoulli; Jonker 1989): nodes p, q with
positions and Euler parameters; local coordinates
``xe = [x_p (3), lam_p (4), x_q (3), lam_q (4)]`` (m, -, m, -), R(lam) the quadratic
rotation matrix of :func:`periodyn.kernels.elements.jets.rotation`.

par (19,) = [l0, A_p (3x3), A_q (3x3)], row-major: l0 the reference length (m); row k of
A_p holds the section axis t_k of node p in p's body frame (t_1 along the beam, t_2 and
t_3 the principal section axes y and z), so ``t_k^p = R(lam_p) A_p[k]``; in the reference
configuration both nodes' axes coincide and t_1 points from p to q.

Deformation modes, in this order, with u = x_q - x_p the chord:
  elongation  ``l - l0 + l0/30 (2 a_p^2 - a_p a_q + 2 a_q^2 + 2 b_p^2 - b_p b_q + 2 b_q^2)`` (m)
  torsion     ``atan2(t_3^p.t_2^q - t_2^p.t_3^q, t_2^p.t_2^q + t_3^p.t_3^q) + b_p a_q - b_q a_p`` (rad)
  bending_z_p ``a_p = atan2(-t_2^p.u, t_1^p.u)``, bending_z_q ``a_q`` likewise (rad)
  bending_y_p ``b_p = atan2(t_3^p.u, t_1^p.u)``,  bending_y_q ``b_q`` likewise (rad)
a = end rotations about the section z axis (bending in the section's x-y plane), b about
the y axis, both relative to the chord and counter-clockwise. The second-order terms make
the geometric stiffness consistent with the cubic Hermite centre line: the elongation's
are its shortening by bowing (the planar beam's, in both planes); the torsion's make it
the integral of the sections' torsional curvature along the Hermite line (the end-frame
angle alone differs from it by ``b_p a_q - b_q a_p``, second order). Each mode is
homogeneous of degree 0 in lam_p and in lam_q (ratios of dot products), so it does not
depend on the Euler parameters' normalization. Derivatives up to third order are exact
(Taylor jets).

Inertia (ipar, see :func:`inertia`): consistent mass of the cubic Hermite centre line
``r(s) = N1 x_p + N2 x_q + N3 l0 t_1^p + N4 l0 t_1^q`` (exact for rigid motions), and the
rotary inertia of the sections, ``1/2 sum_k E_k |t_k'|^2`` per unit length with E the
sections' second moments of mass about their axes (kg m): either lumped at the nodes
(half the element's at each end) or consistent, with the section axes interpolated as
``t_k(s) = W0 c_k + W1 t_k^p + W2 t_k^q`` (W the slopes of the Hermite functions, c the
chord frame: c_1 = u/|u|, c_2 the part of t_2^p + t_2^q normal to c_1, normalized,
c_3 = c_1 x c_2), which gives the Hermite slopes in bending and a linear twist.
"""

import numpy as np
from numba import njit

from . import jets
from .spatial_joints import store
from .vector_inertia import add_vector_inertia

NDOF = 14
NMODE = 6
NPAR = 19
NIPAR = NPAR + 5
HERMITE_MASS = np.array([[13 / 35, 9 / 70, 11 / 210, -13 / 420], [9 / 70, 13 / 35, 13 / 420, -11 / 210],
                         [11 / 210, 13 / 420, 1 / 105, -1 / 140], [-13 / 420, -11 / 210, -1 / 140, 1 / 105]])
"""int_0^1 N_i N_j ds of the cubic Hermite functions (N1, N2, N3, N4)."""
HERMITE_WEIGHTS = np.array([0.5, 0.5, 1 / 12, -1 / 12])
SLOPE_MASS = np.array([[6 / 5, -1 / 10, -1 / 10], [-1 / 10, 2 / 15, -1 / 30], [-1 / 10, -1 / 30, 2 / 15]])
"""int_0^1 W_i W_j ds of the section interpolation W = (6s - 6s^2, N3', N4')."""


@njit(cache=True)
def chord(xe, ip, iq, out):
    """out (3, size(n)) = jets of u = x_q - x_p over n local coordinates, x_p at local
    positions ip..ip+2 and x_q at iq..iq+2 (values from xe[0:3], xe[7:10])."""
    out[:] = 0.0
    for c in range(3):
        out[c, 0] = xe[7 + c] - xe[c]
        out[c, 1 + ip + c] = -1.0
        out[c, 1 + iq + c] = 1.0


@njit(cache=True, inline="always")  # its callers pass literal ints: one kernel each otherwise
def axes(xe, par, node, offset, out):
    """out (3, 3, size(n)): jets of the section axes ``t_k = R(lam) A[k]`` of node 0 (p) or
    1 (q), its Euler parameters at local positions offset..offset+3."""
    R = np.empty((3, 3, out.shape[2]))
    jets.rotation_seeded(xe[3 + 7 * node:7 + 7 * node], offset, R)
    A = par[1 + 9 * node:10 + 9 * node]
    for k in range(3):
        for c in range(3):
            jets.lincomb(A[3 * k], R[c, 0], A[3 * k + 1], R[c, 1], out[k, c])
            jets.lincomb(1.0, out[k, c], A[3 * k + 2], R[c, 2], out[k, c])


@njit(cache=True)
def _bow(a, b, tmp, out):
    """out += a (2a - b) + 2 b b (jets)."""
    jets.lincomb(2.0, a, -1.0, b, tmp)
    jets.mul(a, tmp, tmp)
    jets.add(out, tmp, out)
    jets.mul(b, b, tmp)
    jets.lincomb(1.0, out, 2.0, tmp, out)


# local coordinates of the partial computations: a node's bending angles depend on
# (x_p, x_q, its lam) only, the end-frame twist on (lam_p, lam_q) only
BEND_P = np.arange(10)
BEND_Q = np.array([0, 1, 2, 7, 8, 9, 10, 11, 12, 13])
TWIST = np.array([3, 4, 5, 6, 10, 11, 12, 13])


@njit(cache=True)
def _bending(xe, par, node, a, b):
    """Embedded jets a (about z), b (about y) of the end rotations of node 0 or 1."""
    m = jets.size(10)
    u = np.empty((3, m))
    chord(xe, 0, 3 + 4 * (1 - node), u)
    t = np.empty((3, 3, m))
    axes(xe, par, node, 3 + 3 * node, t)
    dots = np.empty((3, m))
    for k in range(3):
        jets.dot3(t[k], u, dots[k])
    angle = np.empty(m)
    jets.scale(dots[1], -1.0, dots[1])
    jets.atan2(dots[1], dots[0], angle)
    index = BEND_P if node == 0 else BEND_Q
    jets.embed(angle, index, a)
    jets.atan2(dots[2], dots[0], angle)
    jets.embed(angle, index, b)


@njit(cache=True)
def _twist(xe, par, out):
    """Embedded jet of the end-frame twist angle atan2(t3p.t2q - t2p.t3q, t2p.t2q + t3p.t3q)."""
    m = jets.size(8)
    tp = np.empty((3, 3, m))
    tq = np.empty((3, 3, m))
    axes(xe, par, 0, 0, tp)
    axes(xe, par, 1, 4, tq)
    s = np.empty(m)
    c = np.empty(m)
    tmp = np.empty(m)
    jets.dot3(tp[2], tq[1], s)
    jets.dot3(tp[1], tq[2], tmp)
    jets.sub(s, tmp, s)
    jets.dot3(tp[1], tq[1], c)
    jets.dot3(tp[2], tq[2], tmp)
    jets.add(c, tmp, c)
    jets.atan2(s, c, tmp)
    jets.embed(tmp, TWIST, out)


@njit(cache=True)
def deformation(xe, par, D, Dx, Dxx, Dxxx):
    """Overwrite D[:6], Dx[:6, :14], Dxx[:6, :14, :14], Dxxx[:6, :14, :14, :14] with the
    deformation modes and their derivatives w.r.t. xe (14,)."""
    m = jets.size(NDOF)
    l0 = par[0]
    ang = np.empty((4, m))      # a_p, a_q, b_p, b_q
    for node in range(2):
        _bending(xe, par, node, ang[node], ang[2 + node])
    out = np.empty(m)
    tmp = np.empty(m)
    # torsion
    _twist(xe, par, out)
    jets.mul(ang[2], ang[1], tmp)
    jets.add(out, tmp, out)
    jets.mul(ang[3], ang[0], tmp)
    jets.sub(out, tmp, out)
    store(out, 1, NDOF, D, Dx, Dxx, Dxxx)
    # elongation with the bowing of both planes
    u = np.empty((3, m))
    chord(xe, 0, 7, u)
    jets.dot3(u, u, tmp)
    jets.sqrt(tmp, out)
    out[0] -= l0
    bow = np.zeros(m)
    _bow(ang[0], ang[1], tmp, bow)
    _bow(ang[2], ang[3], tmp, bow)
    jets.lincomb(1.0, out, l0 / 30.0, bow, out)
    store(out, 0, NDOF, D, Dx, Dxx, Dxxx)
    for k in range(4):
        store(ang[k], 2 + k, NDOF, D, Dx, Dxx, Dxxx)


@njit(cache=True)
def _chord_frame(u, t, out):
    """out (3, 3, size(14)): chord frame c_1 = u/|u|, c_2 = normalized part of
    t_2^p + t_2^q normal to c_1, c_3 = c_1 x c_2."""
    m = u.shape[1]
    s = np.empty(m)
    w = np.empty((3, m))
    jets.dot3(u, u, s)
    jets.sqrt(s, s)
    jets.reciprocal(s, s)
    for c in range(3):
        jets.mul(u[c], s, out[0, c])
        jets.add(t[0, 1, c], t[1, 1, c], w[c])
    jets.dot3(w, out[0], s)
    tmp = np.empty(m)
    for c in range(3):
        jets.mul(s, out[0, c], tmp)
        jets.sub(w[c], tmp, w[c])
    jets.dot3(w, w, s)
    jets.sqrt(s, s)
    jets.reciprocal(s, s)
    for c in range(3):
        jets.mul(w[c], s, out[1, c])
    jets.cross3(out[0], out[1], out[2])


@njit(cache=True)
def inertia(xe, ve, ae, ipar, gravity, Me, re, Ce, Ke):
    """Add the beam's inertia to the local arrays (leading 14 coordinates): Me += mass
    matrix, re += ``M a`` + convective terms - distributed gravity, Ce += d re / d ve,
    Ke += d re / d xe at fixed ve, ae. gravity (3,) m/s^2.

    ipar (24,) = [par (19), rhoA (kg/m), E_1, E_2, E_3 (kg m, second moments of mass per
    length about the section axes, ``E = tr(J)/2 - J`` of the sections' rotary inertias
    J = (rhoJ, rhoI_y, rhoI_z); an E_k may be negative, e.g. E_1 = -rhoJ/2 when the bending
    rotary inertias are dropped: only J must be non-negative), lumped (1.0: rotary inertia
    lumped at the nodes, 0.0: consistent)]."""
    n = NDOF
    m = jets.size(n)
    l0 = ipar[0]
    rhoA = ipar[NPAR]
    E = ipar[NPAR + 1:NPAR + 4]
    lumped = ipar[NPAR + 4] != 0.0
    u = np.empty((3, m))
    chord(xe, 0, 7, u)
    t = np.empty((2, 3, 3, m))
    for node in range(2):
        axes(xe, ipar, node, 3 + 7 * node, t[node])
    nrot = 6 if lumped else 9
    g = np.zeros((4 + nrot, 3, m))
    mass = np.zeros((4 + nrot, 4 + nrot))
    weights = np.zeros(4 + nrot)
    for node in range(2):
        for c in range(3):
            g[node, c, 0] = xe[7 * node + c]
            g[node, c, 1 + 7 * node + c] = 1.0
        jets.scale(t[node, 0, 0], l0, g[2 + node, 0])
        jets.scale(t[node, 0, 1], l0, g[2 + node, 1])
        jets.scale(t[node, 0, 2], l0, g[2 + node, 2])
    mass[:4, :4] = rhoA * l0 * HERMITE_MASS
    weights[:4] = rhoA * l0 * HERMITE_WEIGHTS
    if lumped:
        for node in range(2):
            for k in range(3):
                i = 4 + 3 * node + k
                g[i] = t[node, k]
                mass[i, i] = 0.5 * l0 * E[k]
    else:
        c = np.empty((3, 3, m))
        _chord_frame(u, t, c)
        for k in range(3):
            i = 4 + 3 * k
            g[i] = c[k]
            g[i + 1] = t[0, k]
            g[i + 2] = t[1, k]
            mass[i:i + 3, i:i + 3] = l0 * E[k] * SLOPE_MASS
    add_vector_inertia(g, mass, weights, ve[:n], ae[:n], gravity, Me[:n, :n], re[:n], Ce[:n, :n], Ke[:n, :n])
