"""Planar beam element (SPACAR-style, Euler-Bernoulli): nodes p, q with positions and
orientation angles; local coordinates ``xe = [x_p, y_p, phi_p, x_q, y_q, phi_q]``
(m, m, rad, m, m, rad). par = [l0, c_p, c_q] with c the reference offsets making the
end tangents ``psi_p = phi_p + c_p``, ``psi_q = phi_q + c_q`` parallel to the chord in the
reference configuration.

Deformation modes: end rotations relative to the chord (rad, counter-clockwise)
``theta_p = psi_p - alpha``, ``theta_q = psi_q - alpha`` (wrapped to (-pi, pi]), and the
elongation of the centre line including the second-order bending (bowing) terms
``e1 = l - l0 + l0 (2 theta_p^2 - theta_p theta_q + 2 theta_q^2) / 30`` (m), whose
second derivatives give the consistent geometric stiffness. Mode order:
(elongation, bending_p, bending_q).

Inertia: consistent mass of the cubic Hermite interpolation of the position
``r(s) = N1 x_p + N2 x_q + N3 l0 t(psi_p) + N4 l0 t(psi_q)``, ``t(psi) = (cos, sin)``;
exact for rigid motions. mass[i, j] = rhoA l0 int N_i N_j ds, weights[i] = rhoA l0 int N_i ds.
Rotary inertia of the cross-sections (optional): the section rotation is interpolated as
``psi(s) = W0 alpha + W1 phi_p + W2 phi_q`` (+ const), ``W = (6s - 6s^2, N3', N4')``, and
rotary[i, j] = rhoI l0 int W_i W_j ds (kg m^2).

Inertia parameters ``ipar`` (IPAR_SIZE = 32): ``[l0, c_p, c_q, mass (4x4 row-major, kg),
weights (4, kg), rotary (3x3 row-major, kg m^2)]``; :func:`pack_inertia` builds it.
"""

import numpy as np
from numba import njit

from .planar_geometry import chord

IPAR_SIZE = 32


def pack_inertia(par, mass, weights, rotary):
    """ipar (32,) from par = [l0, c_p, c_q], mass (4,4) kg, weights (4,) kg, rotary (3,3) kg m^2."""
    return np.concatenate([np.asarray(par, dtype=float)[:3], np.ravel(mass), np.ravel(weights), np.ravel(rotary)])


@njit(cache=True)
def _wrap(angle):
    return (angle + np.pi) % (2.0 * np.pi) - np.pi


@njit(cache=True)
def deformation(xe, par, D, Dx, Dxx, Dxxx):
    """Overwrite D (3,), Dx (3,6), Dxx (3,6,6), Dxxx (3,6,6,6) with the deformation
    modes and their derivatives w.r.t. xe (6,)."""
    n = 6
    l0 = par[0]
    length, alpha, L1, L2, L3, A1, A2, A3 = chord(xe, 0, 3, n)
    theta = np.empty(2)
    theta[0] = _wrap(xe[2] + par[1] - alpha)
    theta[1] = _wrap(xe[5] + par[2] - alpha)
    # theta_k derivatives: unit entry at its own angle minus the chord-angle derivatives
    T1 = np.empty((2, n))
    for k in range(2):
        T1[k] = -A1
    T1[0, 2] += 1.0
    T1[1, 5] += 1.0
    bow1 = np.empty(2)  # d bow / d theta
    bow1[0] = l0 / 30.0 * (4.0 * theta[0] - theta[1])
    bow1[1] = l0 / 30.0 * (4.0 * theta[1] - theta[0])
    bow2 = np.empty((2, 2))  # d2 bow / d theta2
    bow2[0, 0] = 4.0 * l0 / 30.0
    bow2[1, 1] = 4.0 * l0 / 30.0
    bow2[0, 1] = -l0 / 30.0
    bow2[1, 0] = -l0 / 30.0
    bow = l0 / 30.0 * (2.0 * theta[0] ** 2 - theta[0] * theta[1] + 2.0 * theta[1] ** 2)
    D[0] = length - l0 + bow
    D[1] = theta[0]
    D[2] = theta[1]
    s1 = bow1[0] + bow1[1]  # theta second/third derivatives are both -A2, -A3
    for a in range(n):
        Dx[0, a] = L1[a] + bow1[0] * T1[0, a] + bow1[1] * T1[1, a]
        Dx[1, a] = T1[0, a]
        Dx[2, a] = T1[1, a]
        for b in range(n):
            q2 = 0.0
            for k in range(2):
                for m in range(2):
                    q2 += bow2[k, m] * T1[k, a] * T1[m, b]
            Dxx[0, a, b] = L2[a, b] + q2 - s1 * A2[a, b]
            Dxx[1, a, b] = -A2[a, b]
            Dxx[2, a, b] = -A2[a, b]
            for c in range(n):
                q3 = 0.0
                for k in range(2):
                    for m in range(2):
                        # d/dx of bow2 T_k T_m summed, with T_k,xx = -A2 for every k
                        q3 -= bow2[k, m] * (A2[a, c] * T1[m, b] + T1[k, a] * A2[b, c]
                                            + A2[a, b] * T1[m, c])
                Dxxx[0, a, b, c] = L3[a, b, c] + q3 - s1 * A3[a, b, c]
                Dxxx[1, a, b, c] = -A3[a, b, c]
                Dxxx[2, a, b, c] = -A3[a, b, c]


@njit(cache=True)
def inertia(xe, ve, ae, ipar, gravity, M, r, C, K):
    """Add the beam's consistent inertia to the local arrays (6 coordinates):
    M += mass matrix (kg, kg m, kg m^2), r += ``M a - f`` (inertia incl. the convective
    terms, minus distributed gravity), C += d r / d ve, K += d r / d xe at fixed ve, ae.
    ipar (>= 32,) as in the module docstring, gravity (2,) m/s^2."""
    for k in range(23, 32):
        if ipar[k] != 0.0:
            _rotary_inertia(xe, ve, ae, np.ascontiguousarray(ipar[23:32]).reshape((3, 3)), M, r, C, K)
            break
    l0 = ipar[0]
    # G[i]: d g_i / d xe (2,6); gdd[i]: acceleration of g_i; H[i]: d gdd_i / d ve;
    # P[i]: d gdd_i / d xe at fixed ve, ae
    G = np.zeros((4, 2, 6))
    gdd = np.zeros((4, 2))
    H = np.zeros((4, 2, 6))
    P = np.zeros((4, 2, 6))
    G[0, 0, 0] = 1.0
    G[0, 1, 1] = 1.0
    G[1, 0, 3] = 1.0
    G[1, 1, 4] = 1.0
    gdd[0, 0] = ae[0]
    gdd[0, 1] = ae[1]
    gdd[1, 0] = ae[3]
    gdd[1, 1] = ae[4]
    tang = np.empty((2, 2))
    for k in range(2):
        col = 2 + 3 * k
        psi = xe[col] + ipar[1 + k]
        t0 = np.cos(psi)
        t1 = np.sin(psi)
        tang[k, 0] = t0
        tang[k, 1] = t1
        w = ve[col]
        acc = ae[col]
        G[2 + k, 0, col] = -l0 * t1
        G[2 + k, 1, col] = l0 * t0
        gdd[2 + k, 0] = l0 * (-acc * t1 - w * w * t0)
        gdd[2 + k, 1] = l0 * (acc * t0 - w * w * t1)
        H[2 + k, 0, col] = -2.0 * l0 * w * t0
        H[2 + k, 1, col] = -2.0 * l0 * w * t1
        P[2 + k, 0, col] = l0 * (-acc * t0 + w * w * t1)
        P[2 + k, 1, col] = l0 * (-acc * t1 - w * w * t0)
    for i in range(4):
        bi = np.zeros(2)
        for j in range(4):
            mij = ipar[3 + 4 * i + j]
            if mij == 0.0:
                continue
            for c in range(2):
                bi[c] += mij * gdd[j, c]
            for a in range(6):
                for b in range(6):
                    s_m = 0.0
                    s_c = 0.0
                    s_k = 0.0
                    for c in range(2):
                        s_m += G[i, c, a] * G[j, c, b]
                        s_c += G[i, c, a] * H[j, c, b]
                        s_k += G[i, c, a] * P[j, c, b]
                    M[a, b] += mij * s_m
                    C[a, b] += mij * s_c
                    K[a, b] += mij * s_k
        for c in range(2):
            bi[c] -= ipar[19 + i] * gravity[c]
        for a in range(6):
            r[a] += G[i, 0, a] * bi[0] + G[i, 1, a] * bi[1]
        if i >= 2:
            # derivative of G_i^T b_i through the rotating tangent
            col = 2 + 3 * (i - 2)
            K[col, col] -= l0 * (tang[i - 2, 0] * bi[0] + tang[i - 2, 1] * bi[1])


@njit(cache=True)
def _rotary_inertia(xe, ve, ae, rotary, M, r, C, K):
    """Rotary inertia of the sections: interpolated quantities h = (alpha, phi_p, phi_q)
    with gradients Hg (3,6); only alpha has Hessian A2 and third derivative A3."""
    n = 6
    A1, A2, A3 = chord(xe, 0, 3, n)[5:]
    Hg = np.zeros((3, n))
    Hg[0] = A1
    Hg[1, 2] = 1.0
    Hg[2, 5] = 1.0
    A2v = A2 @ ve           # Hessian of alpha times velocity
    hdd = Hg @ ae           # accelerations of h
    hdd[0] += ve @ A2v
    alpha_x = A2 @ ae       # d(alpha'')/dx at fixed ve, ae
    for a in range(n):
        for b in range(n):
            for c in range(n):
                alpha_x[a] += A3[a, b, c] * ve[b] * ve[c]
    B = rotary @ hdd
    for a in range(n):
        r[a] += Hg[0, a] * B[0] + Hg[1, a] * B[1] + Hg[2, a] * B[2]
        for b in range(n):
            K[a, b] += A2[a, b] * B[0]
            for i in range(3):
                for j in range(3):
                    M[a, b] += rotary[i, j] * Hg[i, a] * Hg[j, b]
                # only h_0 = alpha depends non-linearly on x
                C[a, b] += rotary[i, 0] * Hg[i, a] * 2.0 * A2v[b]
                K[a, b] += rotary[i, 0] * Hg[i, a] * alpha_x[b]
