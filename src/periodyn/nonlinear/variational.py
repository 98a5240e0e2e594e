"""Variational equations of the stabilized index-1 equations of motion, integrated in
phase time alongside the trajectories (the monodromy matrix without finite differences).

State y = (q, q') (2n,) with q' = dq/dt; independent variable the phase tau = omega t
(rad), so segment boundaries 2 pi nu i / N do not move with omega and the omega
sensitivity is a plain parameter sensitivity. dy/dtau = G(tau, y) = (q', q'')/omega.

Jacobian of the accelerations q''(q, q') (the ``A_q``, ``A_v`` below), analytically from
the DAE's Jacobians: with ``A = [[M, Phi_q^T], [Phi_q, 0]]``, ``c = gamma - 2 a (Phi_q q'
+ Phi_t) - a^2 Phi`` (Baumgarte rate a),

    A [dq''; dlam] = [f_q - (M q'')_q - sum lam_k Phi_k,qq ; c_q - (Phi_q q'')_q] dq
                   + [f_q'; c_q'] dq',

where (Phi_q x)_q has rows x^T Phi_k,qq (``constraint_hessian`` with unit multipliers)
and the derivatives of the acceleration-level terms (Phi_t, gamma) are central
differences of ``constraint_rates`` (step 1e-5 relative; gamma is quadratic in q', so only
the q columns carry a truncation error, ~1e-11). An ODE (m = 0) uses f_q, f_q' and the
mass Jacobian alone. Parameter sensitivities dG/dp (p = omega or a named parameter) are
central differences of G in p (relative step 1e-5), used only in continuation borders.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .integrate import accelerations, baumgarte_rate, saddle_solve, solve

__all__ = ["Flow", "acceleration_jacobians", "flow"]

_FD_REL = 1e-5


def _rate_derivatives(system, q, qd, t, omega, P):
    """Central differences of (Phi_t, gamma) with respect to (q, q'): each (p, m, 2n)."""
    p, n = q.shape
    h = _FD_REL * np.maximum(1.0, np.abs(np.concatenate([q, qd], axis=1)))  # (p, 2n)
    E = np.zeros((p, 2, 2 * n, 2 * n))
    idx = np.arange(2 * n)
    E[:, 0, idx, idx] = h
    E[:, 1, idx, idx] = -h
    Y = np.concatenate([q, qd], axis=1)[:, None, None, :] + E  # (p, 2, 2n, 2n)
    Y = Y.reshape(-1, 2 * n)
    phit, gam = system.constraint_rates(Y[:, :n], Y[:, n:], np.repeat(t, 4 * n), omega, P)
    phit, gam = (np.asarray(x).reshape(p, 2, 2 * n, -1) for x in (phit, gam))
    den = 2 * h[:, None, :]
    return (np.swapaxes(phit[:, 0] - phit[:, 1], 1, 2) / den, np.swapaxes(gam[:, 0] - gam[:, 1], 1, 2) / den)


def acceleration_jacobians(system, q, qd, t, omega, P, a):
    """q'' (p, n), lambda (p, m), dq''/dq and dq''/dq' (p, n, n) at states q, qd (p, n),
    times t (p,) s; a: Baumgarte rate (1/s)."""
    p, n = q.shape
    m = system.m
    M = np.asarray(system.mass(q))
    f = system.force(q, qd, t, omega, P)
    Kq, Kv = system.force_jacobians(q, qd, t, omega, P)
    if m == 0:
        qdd = np.linalg.solve(M, f[..., None])[..., 0]
        if system.mass_jacobian is not None:
            Kq = Kq - system.mass_jacobian(q, qdd)
        D = np.linalg.solve(M, np.concatenate([Kq, Kv], axis=2))
        return qdd, np.zeros((p, 0)), D[:, :, :n], D[:, :, n:]
    Pq = system.constraint_jacobian(q, t, omega, P)
    phi = system.constraint(q, t, omega, P)
    phit, gam = system.constraint_rates(q, qd, t, omega, P)
    rhs_c = gam - 2 * a * (np.einsum("pkn,pn->pk", Pq, qd) + phit) - a * a * phi
    qdd, lam = (x[..., 0] for x in saddle_solve(M, Pq, f[..., None], rhs_c[..., None]))
    if system.mass_jacobian is not None:
        Kq = Kq - system.mass_jacobian(q, qdd)
    Kq = Kq - system.constraint_hessian(q, lam, t, omega, P)
    unit = np.tile(np.eye(m), (p, 1))
    H = np.asarray(system.constraint_hessian(np.repeat(q, m, axis=0), unit, np.repeat(t, m), omega, P))
    H = H.reshape(p, m, n, n)  # Phi_k,qq
    G_a = np.einsum("pkij,pj->pki", H, qdd)  # (Phi_q q'')_q
    G_v = np.einsum("pkij,pj->pki", H, qd)  # (Phi_q q')_q
    dphit, dgam = _rate_derivatives(system, q, qd, t, omega, P)
    c_q = dgam[..., :n] - 2 * a * (G_v + dphit[..., :n]) - a * a * Pq - G_a
    c_v = dgam[..., n:] - 2 * a * (Pq + dphit[..., n:])
    D = saddle_solve(M, Pq, np.concatenate([Kq, Kv], axis=2), np.concatenate([c_q, c_v], axis=2))[0]
    return qdd, lam, D[:, :, :n], D[:, :, n:]


@dataclass(frozen=True, eq=False)
class Flow:
    """Trajectories of b members over one phase span.

    y: end states (b, 2n) = (q, q') in m, rad, m/s, rad/s; columns: (b, 2n, k) derivative
    of the end state along the k start directions given (None without); sensitivity:
    (b, 2n) total derivative of the end state with respect to the parameter (None
    without); samples: (len(t_eval), b, 2n) states at the requested phases (None
    without); nfev: right-hand sides evaluated.
    """

    y: np.ndarray
    columns: np.ndarray | None
    sensitivity: np.ndarray | None
    samples: np.ndarray | None
    nfev: int


def _parameter(system, omega, params, parameter, sign, h):
    """(omega, params) with the parameter moved by sign * h."""
    if parameter is None:
        return omega + sign * h, params
    return omega, dict(params, **{parameter: params[parameter] + sign * h})


def flow(system, omega, y0, tau0, span, *, directions=None, sensitivity=None, parameter=None, params=None,
         rtol=1e-10, atol=1e-12, method="DOP853", baumgarte=None, t_eval=None) -> Flow:
    """Integrate b members from states y0 (b, 2n) at phases tau0 (b,) rad over ``span``
    rad of phase (time span / omega) at driving speed omega (rad/s).

    directions: (b, 2n, k) start directions, their images come back as ``columns``
    (variational equations); sensitivity: (b, 2n) start derivative dy0/dp, integrated with
    dG/dp (p = omega, or ``parameter`` a name in params); t_eval: phases in [0, span] to
    sample. method: any ``solve`` method; implicit ones get the analytic Jacobian.
    """
    P = system.parameters if params is None else params
    y0 = np.atleast_2d(np.asarray(y0, float))
    b, N = y0.shape
    n = N // 2
    tau0 = np.broadcast_to(np.asarray(tau0, float), (b,))
    a = baumgarte_rate(system, omega, baumgarte)
    k = 0 if directions is None else directions.shape[2]
    sens = sensitivity is not None
    if parameter is not None and parameter not in P:
        raise KeyError(parameter)
    hp = _FD_REL * max(abs(omega if parameter is None else P[parameter]), 1e-3)

    def parts(y):
        Y = y[:b * N].reshape(b, N)
        Phi = y[b * N:b * N * (1 + k)].reshape(b, N, k)
        Z = y[b * N * (1 + k):].reshape(b, N) if sens else None
        return Y, Phi, Z

    def accel(Y, sigma, w, PP):
        return accelerations(system, Y[:, :n], Y[:, n:], (tau0 + sigma) / w, w, PP, a)[0]

    def derivatives(sigma, y):
        Y, Phi, Z = parts(y)
        qdd, _, Aq, Av = acceleration_jacobians(system, Y[:, :n], Y[:, n:], (tau0 + sigma) / omega, omega, P, a)
        return Y, Phi, Z, qdd, Aq, Av

    def rhs(sigma, y):
        if not k and not sens:
            Y = y.reshape(b, N)
            return np.concatenate([Y[:, n:], accel(Y, sigma, omega, P)], axis=1).ravel() / omega
        Y, Phi, Z, qdd, Aq, Av = derivatives(sigma, y)
        out = [np.concatenate([Y[:, n:], qdd], axis=1)]
        if k:
            out.append(np.concatenate([Phi[:, n:], Aq @ Phi[:, :n] + Av @ Phi[:, n:]], axis=1))
        if sens:
            Gp = [np.concatenate([Y[:, n:], accel(Y, sigma, w, PP)], axis=1) / w
                  for w, PP in (_parameter(system, omega, P, parameter, s, hp) for s in (1.0, -1.0))]
            dz = (np.einsum("pij,pj->pi", Aq, Z[:, :n]) + np.einsum("pij,pj->pi", Av, Z[:, n:]))
            out.append(np.concatenate([Z[:, n:], dz], axis=1) + omega * (Gp[0] - Gp[1]) / (2 * hp))
        return np.concatenate([o.ravel() for o in out]) / omega

    def jac(sigma, y):
        _, _, _, _, Aq, Av = derivatives(sigma, y)
        blocks = [np.block([[np.zeros((n, n)), np.eye(n)], [Aq[i], Av[i]]]) / omega for i in range(b)]
        return sp.block_diag(blocks + [np.kron(B, np.eye(k)) for B in blocks] * bool(k) + blocks * sens, "csc")

    start = [y0.ravel()]
    if k:
        start.append(np.asarray(directions, float).ravel())
    if sens:
        start.append(np.asarray(sensitivity, float).ravel())
    implicit = method in ("Radau", "BDF", "LSODA")
    t_all = None if t_eval is None else np.append(np.asarray(t_eval, float), float(span))
    sol = solve(rhs, (0.0, float(span)), np.concatenate(start), t_eval=t_all, rtol=rtol, atol=atol, method=method,
                jac=jac if implicit else None)
    Y, Phi, Z = parts(sol.y[:, -1])
    samples = None if t_eval is None else sol.y[:b * N, :-1].T.reshape(-1, b, N)
    return Flow(Y, Phi if k else None, Z if sens else None, samples, int(sol.nfev))
