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
forward differences of G in p (relative step 1e-5), used only in continuation borders.

Three right-hand sides, one mathematics: planar rigid-body DAEs run the fused kernel of
``periodyn.kernels.solvers.rigid2d_flow``; ODEs with a constant mass the lean path (one force and
one Jacobian call per stage, the rest in ``periodyn.kernels.solvers.ode_flow``; its omega
sensitivity is exact in the time-scaling part, see :func:`_ode_rhs`); all others the NumPy
path of :class:`Derivatives`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from ..kernels.solvers.ode_flow import ode_variational_rhs
from ..kernels.solvers.rigid2d_flow import variational_rhs
from ..kernels.solvers.saddle import saddle_accelerations, saddle_jacobians
from .integration import baumgarte_rate, solve

__all__ = ["Derivatives", "Flow", "acceleration_jacobians", "flow"]

_FD_REL = 1e-5
_SENS_ATOL = 1e-6  # absolute error allowed in the parameter sensitivity (continuation borders only)


class Derivatives:
    """Accelerations and their Jacobians at driving speed omega (rad/s), parameters P and
    Baumgarte rate a (1/s), for batches of states; work that does not depend on the state
    (a constant mass matrix, its inverse, the difference patterns) is done once here."""

    def __init__(self, system, omega, P, a):
        self.system, self.omega, self.P, self.a = system, float(omega), P, float(a)
        n, m = system.n, system.m
        self.n, self.m = n, m
        self.M0 = None if system.mass_jacobian is not None else np.array(system.mass(system.q0[None])[0], float)
        if self.M0 is not None and m == 0:
            self.Minv = np.linalg.inv(self.M0)
        self.signs = np.concatenate([np.eye(2 * n), -np.eye(2 * n)])  # (4n, 2n) central-difference pattern

    def _mass(self, q):
        return self.M0[None] if self.M0 is not None else np.ascontiguousarray(self.system.mass(q), float)

    def _stage1(self, q, qd, t, w, P):
        """(q'', lambda, Pq, inverse saddle matrix) at speed w, parameters P."""
        sysm, n, p = self.system, self.n, q.shape[0]
        f = sysm.force(q, qd, t, w, P)
        Pq = sysm.constraint_jacobian(q, t, w, P)
        phit, gam = sysm.constraint_rates(q, qd, t, w, P)
        x, Ai = np.empty((p, n + self.m)), np.empty((p, n + self.m, n + self.m))
        saddle_accelerations(self._mass(q), f, Pq, sysm.constraint(q, t, w, P), phit, gam, qd, self.a, x, Ai)
        return x[:, :n], x[:, n:], Pq, Ai

    def accelerations(self, q, qd, t, w=None, P=None) -> np.ndarray:
        """q'' (p, n) at states q, qd (p, n), times t (p,) s (speed w, parameters P:
        default the evaluator's)."""
        w = self.omega if w is None else w
        P = self.P if P is None else P
        if self.m == 0:
            f = self.system.force(q, qd, t, w, P)
            if self.M0 is not None:
                return f @ self.Minv.T
            return np.linalg.solve(self.system.mass(q), f[..., None])[..., 0]
        return self._stage1(q, qd, t, w, P)[0]

    def _rate_derivatives(self, q, qd, t):
        """Central differences of (Phi_t, gamma) with respect to (q, q'): each (p, m, 2n)."""
        p, n = q.shape
        y = np.concatenate([q, qd], axis=1)
        h = _FD_REL * np.maximum(1.0, np.abs(y))  # (p, 2n)
        Y = (y[:, None, :] + self.signs[None] * h[:, None, :]).reshape(-1, 2 * n)
        phit, gam = self.system.constraint_rates(Y[:, :n], Y[:, n:], np.repeat(t, 4 * n), self.omega, self.P)
        out = []
        for x in (phit, gam):
            x = np.asarray(x).reshape(p, 2, 2 * n, -1)
            out.append(np.ascontiguousarray(np.swapaxes(x[:, 0] - x[:, 1], 1, 2) / (2 * h[:, None, :])))
        return out

    def jacobians(self, q, qd, t):
        """q'' (p, n) and D = [dq''/dq, dq''/dq'] (p, n, 2n) at states q, qd (p, n), times t (p,)."""
        sysm, w, P, n, m = self.system, self.omega, self.P, self.n, self.m
        p = q.shape[0]
        Kq, Kv = sysm.force_jacobians(q, qd, t, w, P)
        if m == 0:
            qdd = self.accelerations(q, qd, t)
            if sysm.mass_jacobian is not None:
                Kq = Kq - sysm.mass_jacobian(q, qdd)
                return qdd, np.linalg.solve(sysm.mass(q), np.concatenate([Kq, Kv], axis=2))
            return qdd, self.Minv @ np.concatenate([Kq, Kv], axis=2)
        qdd, lam, Pq, Ai = self._stage1(q, qd, t, w, P)
        if sysm.mass_jacobian is not None:
            Kq = Kq - sysm.mass_jacobian(q, qdd)
        weights = np.concatenate([lam[:, None, :], np.broadcast_to(np.eye(m), (p, m, m))], axis=1)  # lam, unit rows
        H = np.asarray(sysm.constraint_hessian(np.repeat(q, m + 1, axis=0), weights.reshape(-1, m),
                                               np.repeat(t, m + 1), w, P)).reshape(p, m + 1, n, n)
        dphit, dgam = self._rate_derivatives(q, qd, t)
        D = np.empty((p, n, 2 * n))
        saddle_jacobians(Ai, np.ascontiguousarray(Kq - H[:, 0]), np.ascontiguousarray(Kv), np.ascontiguousarray(H[:, 1:]),
                         qdd, qd, Pq, dphit, dgam, self.a, D)
        return qdd, D


def acceleration_jacobians(system, q, qd, t, omega, P, a):
    """q'' (p, n), dq''/dq and dq''/dq' (p, n, n) at states q, qd (p, n), times t (p,) s;
    a: Baumgarte rate (1/s)."""
    qdd, D = Derivatives(system, omega, P, a).jacobians(q, qd, t)
    return qdd, D[:, :, :system.n], D[:, :, system.n:]


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


def _ode_rhs(system, omega, tau0, y0, P, k, sens, ev, parameter, hp, w, PP, span):
    """Right-hand side of the lean path for ODEs with a constant mass M: per stage one
    force call and, with columns, one force-Jacobian call; the rest is one jitted call
    (:func:`periodyn.kernels.solvers.ode_flow.ode_variational_rhs`). The omega sensitivity is exact in its scaling part:
    in phase time G(tau, y) = (q', M^-1 f(q, q', tau/omega, omega))/omega, so

        dG/domega = -G/omega + (0, M^-1 df/domega|_tau)/omega,

    where df/domega at fixed phase tau is zero for a force that depends on omega and t only
    through omega t (``system.phase_forcing``, checked here on the start states) and else
    a forward difference (relative step 1e-5). A named parameter p adds (0, M^-1 df/dp)/omega
    (forward difference)."""
    b, N = y0.shape
    n, kc = system.n, k + sens
    bN = b * N
    force, fjac = system.force, system.force_jacobians
    Minv = np.zeros((0, 0)) if np.array_equal(ev.M0, np.eye(n)) else np.ascontiguousarray(ev.Minv)
    explicit = sens and (parameter is not None or not _phase_only(system, omega, tau0, y0, P, span))
    scaling = float(parameter is None)
    none = np.zeros((b, n, n))  # Jacobians and df of a call that does not use them
    work = np.empty(n * (kc + 2))

    def rhs(sigma, y):
        t = (tau0 + sigma) / omega
        Y = y[:bN].reshape(b, N)
        q, v = Y[:, :n], Y[:, n:]
        f = force(q, v, t, omega, P)
        Kq, Kv = fjac(q, v, t, omega, P) if kc else (none, none)
        df = (force(q, v, (tau0 + sigma) / w, w, PP) - f) / hp if explicit else none[:, 0]
        out = np.empty_like(y)
        ode_variational_rhs(y, f, Kq, Kv, df, Minv, float(omega), kc, int(sens), scaling, work, out)
        return out

    return rhs


def _phase_only(system, omega, tau0, y0, P, span) -> bool:
    """True when the model declares ``phase_forcing`` (force(q, q', t, omega) a function of
    omega t only); the declaration is checked at two phases of the span, at the first start
    state and a moved one (an InputError when the force moves with omega at a fixed phase)."""
    if not getattr(system, "phase_forcing", False):
        return False
    n = system.n
    tau = tau0[0] + np.array([0.37, 0.81]) * span
    Y = np.stack([y0[0], 1.5 * y0[0] + 0.1])
    q, v = Y[:, :n], Y[:, n:]
    f0, f1 = (system.force(q, v, tau / w, w, P) for w in (omega, 1.001 * omega))
    if not np.allclose(f0, f1, rtol=1e-9, atol=1e-12 * max(1.0, float(np.max(np.abs(f0))))):
        raise InputError(f"model {system.name!r} declares phase_forcing, but its force changes with omega at a fixed "
                         f"phase omega t (by {float(np.max(np.abs(f1 - f0))):.3g} for a 0.1 % change); drop "
                         "phase_forcing=True or make the force a function of omega t only")
    return True


def flow(system, omega, y0, tau0, span, *, directions=None, sensitivity=None, parameter=None, params=None,
         rtol=1e-10, atol=1e-12, method="DOP853", baumgarte=None, t_eval=None, max_step=np.inf) -> Flow:
    """Integrate b members from states y0 (b, 2n) at phases tau0 (b,) rad over ``span``
    rad of phase (time span / omega) at driving speed omega (rad/s).

    directions: (b, 2n, k) start directions, their images come back as ``columns``
    (variational equations); sensitivity: (b, 2n) start derivative dy0/dp, integrated with
    dG/dp (p = omega, or ``parameter`` a name in params); t_eval: phases in [0, span] to
    sample. method: any ``solve`` method; implicit ones get the analytic Jacobian; max_step:
    its largest step in phase (rad; a step of h seconds is omega h).
    baumgarte: stabilization rate (1/s), default omega: constraint drift decays by
    exp(-2 pi) per period, and the steps stay as long as the motion allows (5 omega, the
    default of ``integrate``, takes twice as many steps at rtol 1e-11).
    """
    P = system.parameters if params is None else params
    y0 = np.atleast_2d(np.asarray(y0, float))
    b, N = y0.shape
    n = N // 2
    tau0 = np.broadcast_to(np.asarray(tau0, float), (b,))
    a = baumgarte_rate(system, omega, omega if baumgarte is None else baumgarte)
    k = 0 if directions is None else directions.shape[2]
    sens = sensitivity is not None
    if parameter is not None and parameter not in P:
        raise KeyError(parameter)
    hp = _FD_REL * max(abs(omega if parameter is None else P[parameter]), 1e-3)

    bN, kc = b * N, k + sens  # the sensitivity rides along as the last variational column

    def parts(y):
        return y[:bN].reshape(b, N), y[bN:].reshape(b, N, kc)

    ev = Derivatives(system, omega, P, a)
    w, PP = _parameter(system, omega, P, parameter, 1.0, hp)

    def python_rhs(sigma, y):
        t = (tau0 + sigma) / omega
        (Y, C), out = parts(y), np.empty_like(y)
        O, OC = parts(out)
        q, v = Y[:, :n], Y[:, n:]
        O[:, :n] = v
        if not kc:
            O[:, n:] = ev.accelerations(q, v, t)
            return out / omega
        qdd, D = ev.jacobians(q, v, t)
        O[:, n:] = qdd
        OC[:, :n] = C[:, n:]
        OC[:, n:] = D @ C
        if sens:  # forward difference of G = (q', q'')/omega in p (only the continuation border uses it)
            OC[:, :n, -1] += v * ((omega / w - 1.0) / hp)
            OC[:, n:, -1] += (ev.accelerations(q, v, (tau0 + sigma) / w, w, PP) * (omega / w) - qdd) / hp
        return out / omega

    planar = getattr(system, "planar_arrays", None)
    if planar is None and system.m == 0 and ev.M0 is not None:  # constant-mass ODE: one force (+ Jacobian) call
        rhs = _ode_rhs(system, omega, tau0, y0, P, k, sens, ev, parameter, hp, w, PP, span)
    elif planar is None:
        rhs = python_rhs
    else:  # one jitted call per stage (periodyn.kernels.solvers.rigid2d_flow)
        (model, data), tau0c = planar, np.ascontiguousarray(tau0)
        fused = (float(omega), float(a), n, k, int(sens), hp, float(w), model, *data(P), *data(PP))

        def rhs(sigma, y):  # the jitted twin of python_rhs
            out = np.empty_like(y)
            variational_rhs(float(sigma), y, tau0c, *fused, out)
            return out

    def derivatives(sigma, y):
        Y = y[:bN].reshape(b, N)
        return ev.jacobians(Y[:, :n], Y[:, n:], (tau0 + sigma) / omega)

    def jac(sigma, y):
        _, D = derivatives(sigma, y)
        blocks = [np.block([[np.zeros((n, n)), np.eye(n)], [D[i]]]) / omega for i in range(b)]
        return sp.block_diag(blocks + [np.kron(B, np.eye(kc)) for B in blocks] * bool(kc), "csc")

    C0 = np.zeros((b, N, kc))
    if k:
        C0[:, :, :k] = directions
    tol = np.full((1 + kc) * bN, float(atol))
    if sens:
        C0[:, :, -1] = sensitivity
        tol[bN:].reshape(bN, kc)[:, -1] = _SENS_ATOL  # loose: the sensitivity must not shorten the steps
    implicit = method in ("Radau", "BDF", "LSODA")
    # only the sampled phases and the end are kept (not every step: a stiff system takes
    # hundreds of thousands of explicit steps, each holding the 2n(k + 1) states)
    t_all = np.append([] if t_eval is None else np.asarray(t_eval, float), float(span))
    sol = solve(rhs, (0.0, float(span)), np.concatenate([y0.ravel(), C0.ravel()]), t_eval=t_all, rtol=rtol, atol=tol,
                method=method, jac=jac if implicit else None, max_step=max_step)
    Y, C = parts(sol.y[:, -1])
    samples = None if t_eval is None else sol.y[:bN, :-1].T.reshape(-1, b, N)
    return Flow(Y, C[:, :, :k] if k else None, C[:, :, -1] if sens else None, samples, int(sol.nfev))
