"""Jitted kernels for planar rigid multibody DAEs (``periodyn.model.rigid2d`` builder).

Convention (as for every kernel module): float64 arrays, int64 index arrays, integer
loop bounds, no Python objects, caller-allocated ``out`` arrays that the kernel fills
completely (it zeroes them first). The leading axis of ``q`` (p, n) is a batch axis:
time samples of one orbit or several trajectories integrated together; ``t`` is (p,).

Bodies: ``coord[b]`` first coordinate index of body b (x, y, then phi if ``rot[b]``).
Revolute joints, one per row of ``jint`` (a, b, row) / ``jflt`` (sa(2), sb(2), g0(2),
gc(2), gs(2)): constraint rows ``row, row+1`` are
``Phi = r_b + R(phi_b) sb - r_a - R(phi_a) sa`` with body a = -1 meaning the ground
point ``g(t) = g0 + gc cos(w t) + gs sin(w t)`` (prescribed base motion).
Sliders (``sint`` (b, row), ``sflt`` (s(2), normal(2), r0(2))): one row
``Phi = n . (r_b + R(phi_b) s - r0)``.
Springs (``kint`` (i, j), ``kflt`` (k1, k3, c, offset)): with ``d = q_i - q_j - offset``
(``q_j = 0`` for j = -1) the force ``-k1 d - k3 d^3 - c d'`` acts on i and its negative on j.
Loads (``lint`` (i,), ``lflt`` (a, b, harmonic)): ``a cos(h w t) + b sin(h w t)`` on q_i.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _point(q, k, c, rot, s0, s1):
    """World position of local point s on body with first coordinate c, and dR/dphi s."""
    x = q[k, c]
    y = q[k, c + 1]
    if rot:
        ph = q[k, c + 2]
        cs = np.cos(ph)
        sn = np.sin(ph)
        rx = cs * s0 - sn * s1
        ry = sn * s0 + cs * s1
        return x + rx, y + ry, -ry, rx
    return x + s0, y + s1, 0.0, 0.0


@njit(cache=True)
def constraint_values(q, t, w, coord, rot, jint, jflt, sint, sflt, out):
    """Phi(q, t): out (p, m)."""
    p = q.shape[0]
    for k in range(p):
        ct = np.cos(w * t[k])
        st = np.sin(w * t[k])
        for e in range(jint.shape[0]):
            a, b, row = jint[e, 0], jint[e, 1], jint[e, 2]
            pbx, pby, _, _ = _point(q, k, coord[b], rot[b], jflt[e, 2], jflt[e, 3])
            if a >= 0:
                pax, pay, _, _ = _point(q, k, coord[a], rot[a], jflt[e, 0], jflt[e, 1])
            else:
                pax = jflt[e, 4] + jflt[e, 6] * ct + jflt[e, 8] * st
                pay = jflt[e, 5] + jflt[e, 7] * ct + jflt[e, 9] * st
            out[k, row] = pbx - pax
            out[k, row + 1] = pby - pay
        for e in range(sint.shape[0]):
            b, row = sint[e, 0], sint[e, 1]
            px, py, _, _ = _point(q, k, coord[b], rot[b], sflt[e, 0], sflt[e, 1])
            out[k, row] = sflt[e, 2] * (px - sflt[e, 4]) + sflt[e, 3] * (py - sflt[e, 5])


@njit(cache=True)
def constraint_jacobian(q, coord, rot, jint, jflt, sint, sflt, out):
    """Phi_q: out (p, m, n)."""
    out[:] = 0.0
    for k in range(q.shape[0]):
        for e in range(jint.shape[0]):
            a, b, row = jint[e, 0], jint[e, 1], jint[e, 2]
            cb = coord[b]
            _, _, dbx, dby = _point(q, k, cb, rot[b], jflt[e, 2], jflt[e, 3])
            out[k, row, cb] += 1.0
            out[k, row + 1, cb + 1] += 1.0
            if rot[b]:
                out[k, row, cb + 2] += dbx
                out[k, row + 1, cb + 2] += dby
            if a >= 0:
                ca = coord[a]
                _, _, dax, day = _point(q, k, ca, rot[a], jflt[e, 0], jflt[e, 1])
                out[k, row, ca] -= 1.0
                out[k, row + 1, ca + 1] -= 1.0
                if rot[a]:
                    out[k, row, ca + 2] -= dax
                    out[k, row + 1, ca + 2] -= day
        for e in range(sint.shape[0]):
            b, row = sint[e, 0], sint[e, 1]
            cb = coord[b]
            _, _, dx, dy = _point(q, k, cb, rot[b], sflt[e, 0], sflt[e, 1])
            out[k, row, cb] += sflt[e, 2]
            out[k, row, cb + 1] += sflt[e, 3]
            if rot[b]:
                out[k, row, cb + 2] += sflt[e, 2] * dx + sflt[e, 3] * dy


@njit(cache=True)
def constraint_hessian(q, lam, coord, rot, jint, jflt, sint, sflt, out):
    """sum_k lam_k d^2 Phi_k / dq^2: out (p, n, n); lam (p, m)."""
    out[:] = 0.0
    for k in range(q.shape[0]):
        for e in range(jint.shape[0]):
            a, b, row = jint[e, 0], jint[e, 1], jint[e, 2]
            l0 = lam[k, row]
            l1 = lam[k, row + 1]
            if rot[b]:
                cb = coord[b]
                px, py, _, _ = _point(q, k, cb, rot[b], jflt[e, 2], jflt[e, 3])
                out[k, cb + 2, cb + 2] -= l0 * (px - q[k, cb]) + l1 * (py - q[k, cb + 1])
            if a >= 0 and rot[a]:
                ca = coord[a]
                px, py, _, _ = _point(q, k, ca, rot[a], jflt[e, 0], jflt[e, 1])
                out[k, ca + 2, ca + 2] += l0 * (px - q[k, ca]) + l1 * (py - q[k, ca + 1])
        for e in range(sint.shape[0]):
            b, row = sint[e, 0], sint[e, 1]
            if rot[b]:
                cb = coord[b]
                px, py, _, _ = _point(q, k, cb, rot[b], sflt[e, 0], sflt[e, 1])
                out[k, cb + 2, cb + 2] -= lam[k, row] * (sflt[e, 2] * (px - q[k, cb]) + sflt[e, 3] * (py - q[k, cb + 1]))


@njit(cache=True)
def constraint_rates(q, qd, t, w, coord, rot, jint, jflt, sint, sflt, phi_t, gamma):
    """Phi_t (p, m) and gamma (p, m) with Phi_q q'' = gamma (second time derivative of Phi = 0)."""
    phi_t[:] = 0.0
    gamma[:] = 0.0
    for k in range(q.shape[0]):
        ct = np.cos(w * t[k])
        st = np.sin(w * t[k])
        for e in range(jint.shape[0]):
            a, b, row = jint[e, 0], jint[e, 1], jint[e, 2]
            if rot[b]:
                cb = coord[b]
                px, py, _, _ = _point(q, k, cb, rot[b], jflt[e, 2], jflt[e, 3])
                v2 = qd[k, cb + 2] ** 2
                gamma[k, row] += (px - q[k, cb]) * v2
                gamma[k, row + 1] += (py - q[k, cb + 1]) * v2
            if a >= 0:
                if rot[a]:
                    ca = coord[a]
                    px, py, _, _ = _point(q, k, ca, rot[a], jflt[e, 0], jflt[e, 1])
                    v2 = qd[k, ca + 2] ** 2
                    gamma[k, row] -= (px - q[k, ca]) * v2
                    gamma[k, row + 1] -= (py - q[k, ca + 1]) * v2
            else:
                # Phi = ... - g(t): Phi_t = -g', Phi_tt = -g'' enters gamma as +g''
                phi_t[k, row] = -w * (-jflt[e, 6] * st + jflt[e, 8] * ct)
                phi_t[k, row + 1] = -w * (-jflt[e, 7] * st + jflt[e, 9] * ct)
                gamma[k, row] += -w * w * (jflt[e, 6] * ct + jflt[e, 8] * st)
                gamma[k, row + 1] += -w * w * (jflt[e, 7] * ct + jflt[e, 9] * st)
        for e in range(sint.shape[0]):
            b, row = sint[e, 0], sint[e, 1]
            if rot[b]:
                cb = coord[b]
                px, py, _, _ = _point(q, k, cb, rot[b], sflt[e, 0], sflt[e, 1])
                v2 = qd[k, cb + 2] ** 2
                gamma[k, row] += (sflt[e, 2] * (px - q[k, cb]) + sflt[e, 3] * (py - q[k, cb + 1])) * v2


@njit(cache=True)
def forces(q, qd, t, w, weight, kint, kflt, lint, lflt, out):
    """Applied forces f(q, q', t): out (p, n); weight (n,) constant (gravity) forces."""
    for k in range(q.shape[0]):
        for i in range(q.shape[1]):
            out[k, i] = weight[i]
        for e in range(kint.shape[0]):
            i, j = kint[e, 0], kint[e, 1]
            d = q[k, i] - kflt[e, 3]
            dd = qd[k, i]
            if j >= 0:
                d -= q[k, j]
                dd -= qd[k, j]
            fe = -kflt[e, 0] * d - kflt[e, 1] * d * d * d - kflt[e, 2] * dd
            out[k, i] += fe
            if j >= 0:
                out[k, j] -= fe
        for e in range(lint.shape[0]):
            ph = lflt[e, 2] * w * t[k]
            out[k, lint[e]] += lflt[e, 0] * np.cos(ph) + lflt[e, 1] * np.sin(ph)


@njit(cache=True)
def force_jacobians(q, qd, kint, kflt, out_q, out_qd):
    """df/dq -> out_q (p, n, n), df/dq' -> out_qd (p, n, n)."""
    out_q[:] = 0.0
    out_qd[:] = 0.0
    for k in range(q.shape[0]):
        for e in range(kint.shape[0]):
            i, j = kint[e, 0], kint[e, 1]
            d = q[k, i] - kflt[e, 3]
            if j >= 0:
                d -= q[k, j]
            kq = kflt[e, 0] + 3.0 * kflt[e, 1] * d * d
            c = kflt[e, 2]
            out_q[k, i, i] -= kq
            out_qd[k, i, i] -= c
            if j >= 0:
                out_q[k, i, j] += kq
                out_q[k, j, i] += kq
                out_q[k, j, j] -= kq
                out_qd[k, i, j] += c
                out_qd[k, j, i] += c
                out_qd[k, j, j] -= c
