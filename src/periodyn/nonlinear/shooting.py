"""Shooting for periodic solutions of ``periodyn.DAE`` systems (ODEs and index-3 DAEs).

Unknowns: the state of the r = n - m independent coordinates at t = 0,
``s = (u, u')`` (2r,); the dependent coordinates follow from ``Phi(q, 0) = 0`` (Newton)
and ``Phi_q q' + Phi_t = 0`` (coordinate partitioning fixed at the initial guess). An ODE
(m = 0) is the case u = q. Residual ``R(s) = s(nu T) - s`` with the flow of the stabilized
index-1 integrator (``periodyn.nonlinear.integrate``). Jacobian ``Phi_T - I``: the
monodromy matrix Phi_T in independent coordinates, by central differences of the flow
(step 1e-6 relative) with all 4r perturbed trajectories integrated in one batch (same
step sequence, so integration errors cancel in the differences). Its eigenvalues at
the converged orbit are the Floquet multipliers from direct integration.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ..errors import InputError
from ..floquet import FloquetExponents
from ..periodic import PeriodicSolution
from ..spectra import fourier_coefficients
from .implicit import STEPS, implicit_shooting
from .integrate import consistent_state, integrate
from .newton import newton

__all__ = ["ShootingProblem", "shooting", "start_state"]

_FD = 1e-6


class ShootingProblem:
    """Shooting residual/Jacobian for ``system``; ``reference`` (n,) configuration near the
    orbit at t = 0 fixes the coordinate partition and the Newton start of q_v."""

    def __init__(self, system, reference: np.ndarray, subharmonic: int = 1, rtol: float = 1e-11,
                 atol: float = 1e-12, samples: int = 128):
        self.system = system
        self.nu = int(subharmonic)
        self.rtol, self.atol, self.p = rtol, atol, int(samples)
        self.ref = np.array(reference, float)
        n, m = system.n, system.m
        if m:
            Pq = system.constraint_jacobian(self.ref[None], np.zeros(1), 1.0, system.parameters)[0]
            piv = sla.qr(Pq, pivoting=True, mode="r")[1]
            self.dep = np.sort(piv[:m])
        else:
            self.dep = np.zeros(0, int)
        self.ind = np.setdiff1d(np.arange(n), self.dep)
        self.r = len(self.ind)
        self.size = 2 * self.r

    def full_state(self, s, omega, params):
        """(u, u') -> consistent (q, qd) (n,) at t = 0."""
        q = self.ref.copy()
        q[self.ind] = s[:self.r]
        qd = np.zeros(self.system.n)
        qd[self.ind] = s[self.r:]
        if self.system.m == 0:
            return q, qd
        P = self.system.parameters if params is None else params
        T0 = np.zeros(1)

        def equations(v):
            q[self.dep] = v
            phi = self.system.constraint(q[None], T0, omega, P)[0]
            return phi, self.system.constraint_jacobian(q[None], T0, omega, P)[0][:, self.dep]

        q[self.dep] = newton(equations, q[self.dep], tol=1e-14, max_iter=50, label="dependent coordinates of a "
                             "shooting state", hint="the state is far from the constraint manifold").x
        Pq = self.system.constraint_jacobian(q[None], T0, omega, P)[0]
        phit, _ = self.system.constraint_rates(q[None], qd[None], T0, omega, P)
        qd[self.dep] = -np.linalg.solve(Pq[:, self.dep], Pq[:, self.ind] @ qd[self.ind] + phit[0])
        return q, qd

    def state(self, q, qd) -> np.ndarray:
        return np.concatenate([q[..., self.ind], qd[..., self.ind]], axis=-1)

    def _flow(self, S, omega, params):
        """End states s(nu T) for a batch of start states S (b, 2r)."""
        full = [self.full_state(s, omega, params) for s in S]
        Q = np.array([f[0] for f in full])
        QD = np.array([f[1] for f in full])
        th = integrate(self.system, omega, (0.0, 2 * np.pi * self.nu / omega), Q, QD, t_eval=[2 * np.pi * self.nu / omega],
                       params=params, rtol=self.rtol, atol=self.atol)
        q, qd = (th.q[-1], th.qd[-1]) if th.q.ndim == 3 else (th.q[-1:], th.qd[-1:])
        return self.state(q, qd)

    def residual(self, s, omega, params=None) -> np.ndarray:
        return self._flow(np.asarray(s, float)[None], omega, params)[0] - s

    def residual_jacobian(self, s, omega, params=None):
        """(R (2r,), Phi_T - I (2r, 2r) dense)."""
        s = np.asarray(s, float)
        h = _FD * np.maximum(1.0, np.abs(s))
        E = np.diag(h)
        S = np.vstack([s[None], s + E, s - E])
        F = self._flow(S, omega, params)
        k = self.size
        mono = (F[1:k + 1] - F[k + 1:]).T / (2 * h)
        return F[0] - s, mono - np.eye(k)

    def newton(self, s, omega, params=None, tol=1e-9, max_iter=30):
        """Newton on R(s) = 0 (backtracking: no step that doubles the residual); returns a
        NewtonResult whose jacobian + I is the monodromy matrix at the orbit."""
        return newton(lambda x: self.residual_jacobian(x, omega, params), s, tol=tol, max_iter=max_iter,
                      residual=lambda x: self.residual(x, omega, params), backtrack=9, accept=2.0,
                      label=f"shooting at omega={omega:.6g} rad/s",
                      hint="start from a better guess (IHB solution or longer settling)")

    def exponents(self, jacobian, omega) -> FloquetExponents:
        """Floquet exponents from the shooting Jacobian Phi_T - I at a converged orbit."""
        mu = np.linalg.eigvals(jacobian + np.eye(self.size))
        return FloquetExponents.from_multipliers(mu, float(omega), "shooting", self.nu)

    def solution(self, s, omega, params, residual, iterations, stability, harmonics=None) -> PeriodicSolution:
        """Sample the converged orbit at p points and return its spectra (H = (p-1)//2 or harmonics)."""
        q0, qd0 = self.full_state(s, omega, params)
        T = 2 * np.pi * self.nu / omega
        th = integrate(self.system, omega, (0.0, T), q0, qd0, t_eval=np.arange(self.p) * T / self.p, params=params,
                       rtol=self.rtol, atol=self.atol)
        H = harmonics if harmonics is not None else (self.p - 1) // 2
        sysm = self.system
        lam = fourier_coefficients(th.lam, H) if sysm.m else np.zeros((2 * H + 1, 0), complex)
        return PeriodicSolution(float(omega), fourier_coefficients(th.q, H), None, sysm.coordinate_names,
                                sysm.coordinate_names, float(residual), iterations=int(iterations), method="shooting",
                                subharmonic=self.nu, lambda_harmonics=lam, constraint_names=sysm.constraint_names,
                                stability=stability, parameters=dict(sysm.parameters if params is None else params))


def start_state(system, guess, omega, params=None):
    """Consistent (q, qd) (n,) at t = 0 from a PeriodicSolution, a full state (q, qd) or
    None (``system.q0`` at rest)."""
    if isinstance(guess, PeriodicSolution):
        q, qd = guess(0.0)[0], guess.velocity(0.0)[0]
    elif guess is None:
        q, qd = system.q0, np.zeros(system.n)
    else:
        q, qd = guess
    return consistent_state(system, q, qd, 0.0, omega, params)


def shooting(system, omega: float, *, initial=None, subharmonic: int = 1, settle_periods: int = 0, tol: float = 1e-9,
             max_iter: int = 30, rtol: float = 1e-11, samples: int = 128, params=None, method: str = "adaptive",
             steps: int = STEPS) -> PeriodicSolution:
    """Periodic solution of ``system`` at ``omega`` (rad/s) by shooting.

    initial: PeriodicSolution (e.g. from ``ihb``), a full state (q, qd), or None (rest at
    ``system.q0``); settle_periods: periods integrated before Newton (transient decay);
    tol: residual max-norm of the independent state (m, rad, m/s, rad/s). The result has
    spectra of q and lambda from ``samples`` points of the orbit and the monodromy
    multipliers (2(n - m),). Raises ConvergenceError when Newton fails.

    method: "adaptive" (scipy integration at rtol, finite-difference monodromy) or
    "implicit" (element models only: ``steps`` trapezoidal steps per period in Numba with
    the exact monodromy of the discrete map, :mod:`periodyn.nonlinear.implicit`).
    """
    if not np.isfinite(omega) or omega <= 0:
        raise InputError(f"omega must be a positive driving frequency in rad/s, got {omega!r}")
    if method not in ("adaptive", "implicit"):
        raise InputError(f"method must be 'adaptive' or 'implicit', got {method!r}")
    q, qd = start_state(system, initial, omega, params)
    if method == "implicit":
        return implicit_shooting(system, omega, q, qd, subharmonic=subharmonic, steps=steps,
                                 settle_periods=settle_periods, tol=tol, max_iter=max_iter, samples=samples, params=params)
    if settle_periods:
        T = 2 * np.pi * subharmonic / omega
        th = integrate(system, omega, (0.0, settle_periods * T), q, qd, t_eval=[settle_periods * T], params=params,
                       rtol=1e-9, atol=1e-11)
        q, qd = consistent_state(system, th.q[-1], th.qd[-1], 0.0, omega, params)
    prob = ShootingProblem(system, q, subharmonic, rtol=rtol, samples=samples)
    res = prob.newton(prob.state(q, qd), float(omega), params, tol, max_iter)
    return prob.solution(res.x, omega, params, res.residual, res.iterations, prob.exponents(res.jacobian, omega))
