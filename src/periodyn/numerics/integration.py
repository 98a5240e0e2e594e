"""Time integration of DAE/ODE models (``periodyn.DAE``) as a stabilized index-1 system.

Each right-hand side solves the saddle-point system

    [M    Phi_q^T] [q'']   [f]
    [Phi_q   0   ] [lam] = [gamma - 2 a (Phi_q q' + Phi_t) - a^2 Phi]

(Baumgarte stabilization with rate a, default ``5 omega``: the velocity and position
constraint errors decay like ``exp(-a t)`` instead of drifting). lambda at any time is
the second block of the same solve, so constraint forces come out of the integration.
A leading batch axis integrates several trajectories in one call (used by shooting).
Integrator: scipy DOP853 (rtol 1e-10, atol 1e-12 by default).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from ..errors import ConvergenceError, InputError
from .newton_iteration import least_squares_factor, newton

__all__ = ["TimeHistory", "accelerations", "baumgarte_rate", "saddle_solve", "integrate", "consistent_state",
           "steady_state", "solve"]


@dataclass(frozen=True, eq=False)
class TimeHistory:
    """Integration result: t (k,) s, q and qd (k, n), lam (k, m); nfev right-hand sides."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    lam: np.ndarray
    nfev: int


def baumgarte_rate(system, omega, baumgarte=None) -> float:
    """Stabilization rate a (1/s): ``baumgarte`` or the default 5 omega."""
    if system.constraint_rates is None and system.m:
        raise InputError("time integration of a constrained DAE needs constraint_rates (Phi_t, gamma)")
    return 5.0 * omega if baumgarte is None else float(baumgarte)


def saddle_solve(M, Pq, top, bottom):
    """Solve [[M, Pq^T], [Pq, 0]] [x; lam] = [top; bottom] for a batch: M (p, n, n), Pq
    (p, m, n), top (p, n, k), bottom (p, m, k) -> x (p, n, k), lam (p, m, k). A diagonal
    mass takes the Schur complement on the m multipliers."""
    p, n = M.shape[:2]
    m = Pq.shape[1]
    d = np.diagonal(M, axis1=1, axis2=2)
    if np.all(M == d[:, :, None] * np.eye(n)):
        PMi = Pq / d[:, None, :]
        lam = np.linalg.solve(PMi @ np.swapaxes(Pq, 1, 2), PMi @ top - bottom)
        return (top - np.swapaxes(Pq, 1, 2) @ lam) / d[:, :, None], lam
    A = np.zeros((p, n + m, n + m))
    A[:, :n, :n] = M
    A[:, :n, n:] = np.swapaxes(Pq, 1, 2)
    A[:, n:, :n] = Pq
    sol = np.linalg.solve(A, np.concatenate([top, bottom], axis=1))
    return sol[:, :n], sol[:, n:]


def accelerations(system, q, qd, t, omega, params=None, baumgarte: float | None = None):
    """q'' (p, n) and lambda (p, m) for a batch of states q, qd (p, n) at times t (p,)."""
    P = system.parameters if params is None else params
    a = baumgarte_rate(system, omega, baumgarte)
    M = np.asarray(system.mass(q))
    f = system.force(q, qd, t, omega, P)
    if system.m == 0:
        return np.linalg.solve(M, f[..., None])[..., 0], np.zeros((q.shape[0], 0))
    Pq = system.constraint_jacobian(q, t, omega, P)
    phi = system.constraint(q, t, omega, P)
    phit, gam = system.constraint_rates(q, qd, t, omega, P)
    rhs_c = gam - 2 * a * (np.einsum("pkn,pn->pk", Pq, qd) + phit) - a * a * phi
    qdd, lam = saddle_solve(M, Pq, f[..., None], rhs_c[..., None])
    return qdd[..., 0], lam[..., 0]


def consistent_state(system, q, qd, t, omega, params=None, tol=1e-13, max_iter=50):
    """Project a state (n,) onto Phi = 0 and Phi_q q' + Phi_t = 0 (minimum-norm Gauss-Newton
    for q, least-squares velocity correction). Returns (q, qd)."""
    P = system.parameters if params is None else params
    q = np.array(q, float)
    qd = np.array(qd, float)
    if system.m == 0:
        return q, qd
    T = np.array([t], float)
    q = newton(lambda x: (system.constraint(x[None], T, omega, P)[0], system.constraint_jacobian(x[None], T, omega, P)[0]),
               q, tol=tol, max_iter=max_iter, factor=least_squares_factor,
               label=f"projection onto the constraints at t={t}", hint="start from a configuration near Phi = 0").x
    Pq = system.constraint_jacobian(q[None], T, omega, P)[0]
    phit, _ = system.constraint_rates(q[None], qd[None], T, omega, P)
    qd -= np.linalg.lstsq(Pq, Pq @ qd + phit[0], rcond=None)[0]
    return q, qd


_IMPLICIT = ("Radau", "BDF", "LSODA")


def solve(rhs, t_span, y0, *, t_eval=None, rtol=1e-10, atol=1e-12, method="DOP853", max_step=np.inf, jac=None):
    """The one integrator wrapper: scipy ``solve_ivp`` of y' = rhs(t, y); a failure raises
    ConvergenceError saying what to try. ``jac(t, y)`` -> (N, N) (or a constant array) is the
    analytic Jacobian d rhs / d y used by the implicit methods (Radau, BDF, LSODA); without it
    they difference the right-hand side column by column."""
    if jac is not None and method not in _IMPLICIT:
        raise InputError(f"jac= is used only by the implicit methods {_IMPLICIT}, not by {method!r}; "
                         "drop jac or choose method='Radau'")
    extra = {} if jac is None else {"jac": jac}
    reached = [float(t_span[0])]  # the last time the right-hand side was evaluated at

    def tracked(t, y):
        reached[0] = t
        return rhs(t, y)

    sol = solve_ivp(tracked, t_span, y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol, max_step=max_step,
                    **extra)
    if sol.status != 0:  # with t_eval, sol.t holds only the output times reached (possibly none)
        raise ConvergenceError(f"time integration failed near t={reached[0]:.6g} s (of {t_span[0]:.6g} to "
                               f"{t_span[1]:.6g} s): {sol.message}; lower the tolerances or check the model",
                               float("nan"), int(sol.nfev))
    return sol


def integrate(system, omega, t_span, q0, qd0, *, t_eval=None, params=None, rtol=1e-10, atol=1e-12,
              baumgarte: float | None = None, method: str = "DOP853", max_step: float = np.inf) -> TimeHistory:
    """Integrate from (q0, qd0) (n,) or a batch (b, n) over t_span (s); returns a
    TimeHistory at t_eval (default the solver's steps); for a batch, q is (k, b, n)."""
    q0 = np.atleast_2d(np.asarray(q0, float))
    qd0 = np.atleast_2d(np.asarray(qd0, float))
    b, n = q0.shape
    if n != system.n or qd0.shape != q0.shape:
        raise InputError(f"initial state must have {system.n} coordinates, got q0 {q0.shape}, qd0 {qd0.shape}")

    def rhs(t, y):
        Y = y.reshape(2, b, n)
        qdd, _ = accelerations(system, Y[0], Y[1], np.full(b, t), omega, params, baumgarte)
        return np.concatenate([Y[1].ravel(), qdd.ravel()])

    sol = solve(rhs, t_span, np.concatenate([q0.ravel(), qd0.ravel()]), t_eval=t_eval, rtol=rtol, atol=atol,
                method=method, max_step=max_step)
    Y = sol.y.T.reshape(-1, 2, b, n)
    q, qd = Y[:, 0], Y[:, 1]
    k = len(sol.t)
    lam = accelerations(system, q.reshape(k * b, n), qd.reshape(k * b, n), np.repeat(sol.t, b), omega, params,
                        baumgarte)[1].reshape(k, b, system.m)
    if b == 1:
        q, qd, lam = q[:, 0], qd[:, 0], lam[:, 0]
    return TimeHistory(sol.t, q, qd, lam, int(sol.nfev))


def steady_state(system, omega, q0=None, qd0=None, *, params=None, tol=1e-6, max_periods=2000, rtol=1e-8,
                 atol=1e-10, subharmonic: int = 1):
    """Integrate period by period (period nu 2 pi/omega) from (q0, qd0) (default
    ``system.q0`` at rest) until the state repeats: ``max|y(t+T) - y(t)| <= tol`` (in m,
    rad, m/s, rad/s). Returns (q, qd at a period start, periods integrated, nfev)."""
    T = 2 * np.pi * subharmonic / omega
    q = system.q0 if q0 is None else q0
    qd = np.zeros(system.n) if qd0 is None else qd0
    q, qd = consistent_state(system, q, qd, 0.0, omega, params)
    nfev = 0
    for k in range(1, max_periods + 1):
        th = integrate(system, omega, (0.0, T), q, qd, t_eval=[T], params=params, rtol=rtol, atol=atol)
        nfev += th.nfev
        dq = max(np.max(np.abs(th.q[-1] - q)), np.max(np.abs(th.qd[-1] - qd)))
        q, qd = th.q[-1], th.qd[-1]
        if dq <= tol:
            return q, qd, k, nfev
    raise ConvergenceError(f"no steady state after {max_periods} periods at omega={omega:.6g} rad/s "
                           f"(change per period {dq:.3g}); the response may be quasi-periodic or chaotic",
                           float(dq), max_periods)
