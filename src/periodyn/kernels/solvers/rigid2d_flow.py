"""Jitted right-hand side of the stabilized index-1 equations of motion of a planar rigid
multibody DAE (``periodyn.model.rigid2d``) with its variational equations, in phase time:
one call per integrator stage, no Python between the model kernels
(``periodyn.numerics.variational.flow`` uses it when the DAE carries ``planar_arrays``).

Convention (as for every kernel module): float64 arrays, int64 index arrays, integer loop
bounds, caller-allocated ``out`` filled completely. The state vector y holds b members:
y[:b 2n] the states (q, q') row by row, y[b 2n:] the variational columns (b, 2n, kc),
kc = k start directions plus one parameter-sensitivity column when ``sens``.
``model`` is the tuple (M (1, n, n), weight (n,), kint, kflt, lint, coord, rot, jint,
jraw, sint, sflt) of the builder; ``jflt``/``lflt`` the joint and load data at the
parameters, ``jflt_p``/``lflt_p`` at the moved parameter of the sensitivity.
The mathematics is that of ``periodyn.numerics.variational`` (its docstring), including
the central differences (step 1e-5 relative) of Phi_t and gamma in (q, q').
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .rigid2d import constraint_hessian, constraint_jacobian, constraint_rates, constraint_values, force_jacobians, \
    forces
from .saddle import saddle_accelerations, saddle_jacobians

_FD_REL = 1e-5


@njit(cache=True)
def _accelerations(q, qd, t, w, a, model, jflt, lflt, x, Ai, Pq):
    """(q'', lambda) -> x (b, n + m), inverse saddle matrices -> Ai, Phi_q -> Pq."""
    M, weight, kint, kflt, lint, coord, rot, jint, jraw, sint, sflt = model
    b, n = q.shape
    m = Pq.shape[1]
    f = np.empty((b, n))
    phi = np.empty((b, m))
    phit = np.empty((b, m))
    gam = np.empty((b, m))
    forces(q, qd, t, w, weight, kint, kflt, lint, lflt, f)
    constraint_jacobian(q, coord, rot, jint, jraw, sint, sflt, Pq)
    constraint_values(q, t, w, coord, rot, jint, jflt, sint, sflt, phi)
    constraint_rates(q, qd, t, w, coord, rot, jint, jflt, sint, sflt, phit, gam)
    saddle_accelerations(M, f, Pq, phi, phit, gam, qd, a, x, Ai)


@njit(cache=True)
def _rate_derivatives(q, qd, t, w, model, jflt, dphit, dgam):
    """Central differences of (Phi_t, gamma) in (q, q') -> dphit, dgam (b, m, 2n)."""
    coord, rot, jint, sint, sflt = model[5], model[6], model[7], model[9], model[10]
    b, n = q.shape
    m = dphit.shape[1]
    qq = np.empty((1, n))
    vv = np.empty((1, n))
    tt = np.empty(1)
    pt = np.empty((2, 1, m))
    gg = np.empty((2, 1, m))
    for k in range(b):
        tt[0] = t[k]
        for j in range(2 * n):
            y = q[k, j] if j < n else qd[k, j - n]
            h = _FD_REL * max(1.0, abs(y))
            for s in range(2):
                qq[0] = q[k]
                vv[0] = qd[k]
                step = h if s == 0 else -h
                if j < n:
                    qq[0, j] += step
                else:
                    vv[0, j - n] += step
                constraint_rates(qq, vv, tt, w, coord, rot, jint, jflt, sint, sflt, pt[s], gg[s])
            for i in range(m):
                dphit[k, i, j] = (pt[0, 0, i] - pt[1, 0, i]) / (2 * h)
                dgam[k, i, j] = (gg[0, 0, i] - gg[1, 0, i]) / (2 * h)


@njit(cache=True)
def variational_rhs(sigma, y, tau0, omega, a, n, k, sens, hp, w_p, model, jflt, lflt, jflt_p, lflt_p, out):
    """dy/dsigma of b = len(tau0) members at phase sigma (rad) past tau0 (b,), speed omega
    (rad/s), Baumgarte rate a (1/s); the sensitivity column (``sens`` = 1) is the forward
    difference over hp of G = (q', q'')/omega to speed w_p and the moved parameters."""
    M, weight, kint, kflt, lint, coord, rot, jint, jraw, sint, sflt = model
    b = tau0.shape[0]
    N = 2 * n
    kc = k + sens
    m = jint.shape[0] * 2 + sint.shape[0]
    q = np.empty((b, n))
    v = np.empty((b, n))
    for i in range(b):
        q[i] = y[i * N:i * N + n]
        v[i] = y[i * N + n:(i + 1) * N]
    t = (tau0 + sigma) / omega
    x = np.empty((b, n + m))
    Ai = np.empty((b, n + m, n + m))
    Pq = np.empty((b, m, n))
    _accelerations(q, v, t, omega, a, model, jflt, lflt, x, Ai, Pq)
    for i in range(b):
        out[i * N:i * N + n] = v[i] / omega
        out[i * N + n:(i + 1) * N] = x[i, :n] / omega
    if kc == 0:
        return
    qdd = np.ascontiguousarray(x[:, :n])
    Kq = np.empty((b, n, n))
    Kv = np.empty((b, n, n))
    force_jacobians(q, v, kint, kflt, Kq, Kv)
    H0 = np.empty((b, n, n))
    constraint_hessian(q, np.ascontiguousarray(x[:, n:]), coord, rot, jint, jraw, sint, sflt, H0)
    H = np.empty((b, m, n, n))
    unit = np.zeros((b, m))
    Hi = np.empty((b, n, n))
    for r in range(m):
        unit[:, :] = 0.0
        unit[:, r] = 1.0
        constraint_hessian(q, unit, coord, rot, jint, jraw, sint, sflt, Hi)
        H[:, r] = Hi
    dphit = np.empty((b, m, N))
    dgam = np.empty((b, m, N))
    _rate_derivatives(q, v, t, omega, model, jflt, dphit, dgam)
    D = np.empty((b, n, N))
    saddle_jacobians(Ai, Kq - H0, Kv, H, qdd, v, Pq, dphit, dgam, a, D)
    xp = np.empty((b, n + m))
    if sens:
        _accelerations(q, v, (tau0 + sigma) / w_p, w_p, a, model, jflt_p, lflt_p, xp, Ai, Pq)
    base = b * N
    for i in range(b):
        for r in range(N):
            for c in range(kc):
                if r < n:
                    val = y[base + (i * N + n + r) * kc + c]
                else:
                    val = 0.0
                    for l in range(N):
                        val += D[i, r - n, l] * y[base + (i * N + l) * kc + c]
                out[base + (i * N + r) * kc + c] = val / omega
        if sens:
            for r in range(n):
                out[base + (i * N + r) * kc + kc - 1] += v[i, r] * ((omega / w_p - 1.0) / hp) / omega
                out[base + (i * N + n + r) * kc + kc - 1] += (xp[i, r] * (omega / w_p) - qdd[i, r]) / hp / omega
