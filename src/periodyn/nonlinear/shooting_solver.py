"""Single and multiple shooting for periodic solutions of ``periodyn.DAE`` systems.

The orbit period 2 pi nu / omega is cut into N segments (N = 1: single shooting) starting
at the phases tau_i = 2 pi nu i / N. Unknowns: the states of the r = n - m independent
coordinates at the segment starts, ``s_i = (u_i, u_i')`` (2r each, X = (s_0..s_{N-1}));
the dependent coordinates follow from ``Phi(q, t_i) = 0`` (Newton) and
``Phi_q q' + Phi_t = 0`` (coordinate partition fixed per segment at the reference
configuration). An ODE (m = 0) is the case u = q. Residual ``R_i = s(end of segment i) -
s_{i+1}`` (s_N = s_0), with coordinates declared cyclic compared modulo 2 pi. All
segments are integrated in one batch by the stabilized index-1 integrator in phase time
(``periodyn.numerics.variational``) with the variational equations alongside, so each
evaluation gives R, its block-bidiagonal Jacobian (diagonal blocks the segment transition
matrices G_i, off-diagonal -I) and, for continuation, dR/dp. The monodromy matrix is
G_{N-1} ... G_0 (2r, 2r); its eigenvalues at the converged orbit are the Floquet
multipliers from direct integration.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ..numerics.threads import one_thread
from ..errors import ConvergenceError, InputError
from ..stability.floquet import FloquetExponents
from ..periodic import PeriodicSolution
from ..numerics.spectra import fourier_coefficients
from .elements import as_dae
from .implicit import implicit_shooting
from .options import ShootingOptions, shooting_options
from ..numerics.integration import accelerations, consistent_state
from ..numerics.newton_iteration import newton
from ..numerics.variational import flow

__all__ = ["ShootingProblem", "cyclic_indices", "settle", "shooting", "start_state"]

_FD_REL = 1e-6  # relative step of the parameter derivative of a consistent start state


class ShootingProblem:
    """Shooting residual and Jacobian of ``system``.

    references: (N, n) configurations near the orbit at the N segment starts (fix the
    coordinate partitions and the Newton starts of the dependent coordinates); cyclic:
    indices of coordinates compared modulo 2 pi; parameter: None (the continuation
    parameter is omega) or the name of a model parameter; method: integrator (``solve``);
    max_step: its largest step, s.
    """

    def __init__(self, system, references, subharmonic: int = 1, rtol: float = 1e-11, atol: float = 1e-12,
                 samples: int = 128, cyclic=(), parameter: str | None = None, method: str = "DOP853",
                 max_step: float = np.inf):
        self.system = system
        self.refs = np.atleast_2d(np.array(references, float))
        self.N = self.refs.shape[0]
        self.nu = int(subharmonic)
        self.rtol, self.atol, self.method, self.parameter, self.max_step = rtol, atol, method, parameter, max_step
        self.p = self.N * -(-int(samples) // self.N)  # samples: a multiple of N
        self.taus = 2 * np.pi * self.nu * np.arange(self.N) / self.N
        self.span = 2 * np.pi * self.nu / self.N
        n, m = system.n, system.m
        self.dep = np.zeros((self.N, m), int)
        for i in range(self.N):
            if m:
                Pq = system.constraint_jacobian(self.refs[i][None], np.zeros(1), 1.0, system.parameters)[0]
                self.dep[i] = np.sort(sla.qr(Pq, pivoting=True, mode="r")[1][:m])
        self.ind = np.array([np.setdiff1d(np.arange(n), d) for d in self.dep]).reshape(self.N, n - m)
        self.r = n - m
        self.size = 2 * self.r * self.N
        cyc = np.zeros(n, bool)
        cyc[list(cyclic)] = True
        self.cyclic = cyc
        self.wrap = np.array([np.concatenate([cyc[i], np.zeros(self.r, bool)]) for i in self.ind])
        self._cache = self._samples = (None, None)

    # ------------------------------------------------------------------ states
    def state(self, q, qd, i: int = 0) -> np.ndarray:
        """Independent state (2r,) of segment i from full q, qd (n,)."""
        return np.concatenate([q[..., self.ind[i]], qd[..., self.ind[i]]], axis=-1)

    def unknowns(self, Q, QD) -> np.ndarray:
        """X (2rN,) from full states Q, QD (N, n) at the segment starts."""
        return np.concatenate([self.state(Q[i], QD[i], i) for i in range(self.N)])

    def full_state(self, s, omega, params, i: int = 0):
        """(u, u') of segment i -> consistent (q, qd) (n,) at its start time."""
        sysm, r = self.system, self.r
        q = self.refs[i].copy()
        ind, dep = self.ind[i], self.dep[i]
        q[ind] = s[:r]
        qd = np.zeros(sysm.n)
        qd[ind] = s[r:]
        if sysm.m == 0:
            return q, qd
        T0 = np.array([self.taus[i] / omega])

        def equations(v):
            q[dep] = v
            return sysm.constraint(q[None], T0, omega, params)[0], sysm.constraint_jacobian(q[None], T0, omega,
                                                                                             params)[0][:, dep]

        q[dep] = newton(equations, q[dep], tol=1e-14, max_iter=50, label="dependent coordinates of a shooting state",
                        hint="the state is far from the constraint manifold").x
        Pq = sysm.constraint_jacobian(q[None], T0, omega, params)[0]
        phit, _ = sysm.constraint_rates(q[None], qd[None], T0, omega, params)
        qd[dep] = -np.linalg.solve(Pq[:, dep], Pq[:, ind] @ qd[ind] + phit[0])
        return q, qd

    def _tangent(self, q, qd, omega, params, i):
        """E (2n, 2r): derivative of the consistent full state along the 2r independent
        state directions (the velocity-constraint derivative by central differences)."""
        sysm, n, r = self.system, self.system.n, self.r
        ind, dep = self.ind[i], self.dep[i]
        E = np.zeros((2 * n, 2 * r))
        E[ind, np.arange(r)] = 1.0
        E[n + ind, r + np.arange(r)] = 1.0
        if sysm.m == 0:
            return E
        t = self.taus[i] / omega
        Pq = sysm.constraint_jacobian(q[None], np.array([t]), omega, params)[0]
        h = 1e-6 * np.maximum(1.0, np.abs(q))
        Qp = np.concatenate([q + np.diag(h), q - np.diag(h)])
        T = np.full(2 * n, t)
        v = (np.einsum("pkn,n->pk", sysm.constraint_jacobian(Qp, T, omega, params), qd)
             + sysm.constraint_rates(Qp, np.tile(qd, (2 * n, 1)), T, omega, params)[0])
        W = ((v[:n] - v[n:]) / (2 * h)[:, None]).T  # d(Phi_q q' + Phi_t)/dq (m, n)
        solve_dep = np.linalg.solve(Pq[:, dep], np.eye(sysm.m))
        E[dep, :r] = -solve_dep @ Pq[:, ind]
        E[n + dep] = -solve_dep @ (Pq[:, ind] @ E[n + ind] + W @ E[:n])
        return E

    def _starts(self, X, omega, params):
        S = X.reshape(self.N, 2 * self.r)
        full = [self.full_state(S[i], omega, params, i) for i in range(self.N)]
        return np.array([np.concatenate(f) for f in full])

    def _start_sensitivity(self, X, omega, params):
        """d(consistent start states)/dp (N, 2n) by central differences (zero for an ODE)."""
        Y = np.zeros((self.N, 2 * self.system.n))
        if self.system.m == 0:
            return Y
        v = omega if self.parameter is None else params[self.parameter]
        h = _FD_REL * max(abs(v), 1e-3)
        moved = [(omega + s * h, params) if self.parameter is None else (omega, dict(params, **{self.parameter: v + s * h}))
                 for s in (1.0, -1.0)]
        return (self._starts(X, *moved[0]) - self._starts(X, *moved[1])) / (2 * h)

    # ------------------------------------------------------------------ residual and Jacobian
    def _residual_from(self, X, Yend):
        S = X.reshape(self.N, 2 * self.r)
        nxt = (np.arange(self.N) + 1) % self.N
        n = self.system.n
        R = np.array([np.concatenate([Yend[i, :n][self.ind[j]], Yend[i, n:][self.ind[j]]]) - S[j]
                      for i, j in enumerate(nxt)])
        R[self.wrap[nxt]] -= 2 * np.pi * np.round(R[self.wrap[nxt]] / (2 * np.pi))
        return R.ravel()

    def _select(self, j, Y):
        """Independent components of segment j from full-state vectors Y (2n, ...)."""
        n = self.system.n
        return Y[np.concatenate([self.ind[j], n + self.ind[j]])]

    def residual(self, X, omega, params=None, rtol: float | None = None) -> np.ndarray:
        """R(X) (2rN,) in m, rad, m/s, rad/s (integrated at ``rtol``, default the problem's)."""
        P = self.system.parameters if params is None else params
        X = np.asarray(X, float)
        rtol, atol = (self.rtol, self.atol) if rtol is None else (rtol, 0.1 * rtol)
        f = flow(self.system, omega, self._starts(X, omega, P), self.taus, self.span, params=P, rtol=rtol, atol=atol,
                 method=self.method, max_step=omega * self.max_step)
        return self._residual_from(X, f.y)

    def _key(self, X, omega, P):
        return (X.tobytes(), float(omega), tuple(sorted(P.items())), self.parameter)

    def evaluate(self, X, omega, params=None, sensitivity: bool = False, samples: bool = False,
                 rtol: float | None = None):
        """(R (2rN,), J (2rN, 2rN) dense, dR/dp (2rN,) or None, blocks G_i (N, 2r, 2r)) from
        one batch integration with the variational equations; the latest at the problem's
        tolerance is cached, and with ``samples`` the orbit samples of :meth:`solution`
        are taken on the way. A looser ``rtol`` gives a cheaper approximate J (chord steps)."""
        P = self.system.parameters if params is None else params
        X = np.asarray(X, float)
        key = self._key(X, omega, P)
        if rtol is None and self._cache[0] == key and (self._cache[1][2] is not None or not sensitivity):
            return self._cache[1]
        rtol, atol = (self.rtol, self.atol) if rtol is None else (rtol, 0.1 * rtol)
        Y0 = self._starts(X, omega, P)
        n = self.system.n
        E = np.array([self._tangent(Y0[i, :n], Y0[i, n:], omega, P, i) for i in range(self.N)])
        f = flow(self.system, omega, Y0, self.taus, self.span, directions=E, params=P, rtol=rtol, atol=atol,
                 sensitivity=self._start_sensitivity(X, omega, P) if sensitivity else None, parameter=self.parameter,
                 method=self.method, t_eval=self._sample_phases() if samples else None, max_step=omega * self.max_step)
        if samples:
            self._samples = (key, f.samples)
        R = self._residual_from(X, f.y)
        k = 2 * self.r
        blocks = np.array([self._select((i + 1) % self.N, f.columns[i]) for i in range(self.N)])
        J = -np.eye(self.size)
        J = np.roll(J.reshape(self.N, k, self.N, k), 1, axis=2)  # -I on the block after the diagonal
        for i in range(self.N):
            J[i, :, i] += blocks[i]
        J = J.reshape(self.size, self.size)
        dRdp = None if f.sensitivity is None else np.concatenate(
            [self._select((i + 1) % self.N, f.sensitivity[i]) for i in range(self.N)])
        if rtol == self.rtol:
            self._cache = (key, (R, J, dRdp, blocks))
        return R, J, dRdp, blocks

    def equations(self, X, omega, params=None, sensitivity: bool = False):
        """(R, J) for Newton."""
        return self.evaluate(X, omega, params, sensitivity)[:2]

    def parameter_derivative(self, X, omega, params=None) -> np.ndarray:
        """dR/dp (2rN,) with p = omega or the named parameter."""
        return self.evaluate(X, omega, params, sensitivity=True)[2]

    def monodromy(self, X, omega, params=None) -> np.ndarray:
        """Monodromy matrix G_{N-1} ... G_0 (2r, 2r) in independent coordinates."""
        blocks = self.evaluate(X, omega, params)[3]
        out = blocks[0]
        for B in blocks[1:]:
            out = B @ out
        return out

    def newton(self, X, omega, params=None, tol=1e-9, max_iter=30):
        """Newton on R(X) = 0 (backtracking: no step that doubles the residual); each trial
        is one variational integration, reused by the next iteration."""
        return newton(lambda x: self.equations(x, omega, params), X, tol=tol, max_iter=max_iter, backtrack=9,
                      accept=2.0, label=f"shooting at omega={omega:.6g} rad/s",
                      hint="start from a better guess (IHB solution or longer settling)")

    def exponents(self, X, omega, params=None) -> FloquetExponents:
        """Floquet exponents from the monodromy matrix at a converged orbit."""
        mu = np.linalg.eigvals(self.monodromy(X, omega, params))
        return FloquetExponents.from_multipliers(mu, float(omega), "shooting", self.nu)

    def _sample_phases(self) -> np.ndarray:
        per = self.p // self.N
        return np.arange(per) * self.span / per

    def solution(self, X, omega, params, residual, iterations, stability, harmonics=None) -> PeriodicSolution:
        """Sample the converged orbit at p points and return its spectra (H = (p-1)//2 or
        harmonics); cyclic coordinates are shifted by a multiple of 2 pi to a mean in (-pi, pi]."""
        P = self.system.parameters if params is None else params
        sysm, n = self.system, self.system.n
        X = np.asarray(X, float)
        if self._samples[0] == self._key(X, omega, P):
            samples = self._samples[1]
        else:
            samples = flow(sysm, omega, self._starts(X, omega, P), self.taus, self.span, params=P, rtol=self.rtol,
                           atol=self.atol, method=self.method, t_eval=self._sample_phases(),
                           max_step=omega * self.max_step).samples
        Y = np.swapaxes(samples, 0, 1).reshape(self.p, 2 * n)  # segment by segment: the equispaced grid
        t = np.arange(self.p) * (2 * np.pi * self.nu / omega) / self.p
        c = self.cyclic  # a 2 pi-shifted orbit is the same orbit: mean of a cyclic coordinate in (-pi, pi]
        Y[:, :n][:, c] -= 2 * np.pi * np.round(Y[:, :n][:, c].mean(axis=0) / (2 * np.pi))
        H = harmonics if harmonics is not None else (self.p - 1) // 2
        lam = accelerations(sysm, Y[:, :n], Y[:, n:], t, omega, P)[1]
        lam_h = fourier_coefficients(lam, H) if sysm.m else np.zeros((2 * H + 1, 0), complex)
        return PeriodicSolution(float(omega), fourier_coefficients(Y[:, :n], H), None, sysm.coordinate_names,
                                sysm.coordinate_names, float(residual), iterations=int(iterations), method="shooting",
                                subharmonic=self.nu, lambda_harmonics=lam_h, constraint_names=sysm.constraint_names,
                                stability=stability, parameters=dict(P))


def start_state(system, guess, omega, params=None, t: float = 0.0):
    """Consistent (q, qd) (n,) at time t from a PeriodicSolution, a full state (q, qd) or
    None (``system.q0`` at rest)."""
    if isinstance(guess, PeriodicSolution):
        q, qd = guess(t)[0], guess.velocity(t)[0]
    elif guess is None:
        q, qd = system.q0, np.zeros(system.n)
    else:
        q, qd = guess
    return consistent_state(system, q, qd, t, omega, params)


def settle(system, omega, q, qd, *, periods: int, subharmonic: int = 1, params=None, tol: float = 1e-4,
           rtol: float = 1e-7, atol: float = 1e-9, cyclic=()):
    """Integrate at most ``periods`` periods from (q, qd) with the explicit integrator at a
    loose tolerance, in chunks of 10, until the state changes by at most ``tol`` per period
    (max-norm, m, rad, m/s, rad/s; coordinates with indices in ``cyclic`` modulo 2 pi).
    Returns (q, qd, periods integrated, last change)."""
    n, done, change = system.n, 0, np.inf
    turn = np.zeros(2 * n)
    turn[list(cyclic)] = 2 * np.pi
    y = np.concatenate([q, qd])
    T = 2 * np.pi * subharmonic
    while done < periods and change > tol:
        k = min(10, periods - done)
        f = flow(system, omega, y[None], 0.0, k * T, params=params, rtol=rtol, atol=atol,
                 t_eval=np.arange(1, k) * T)
        ends = np.concatenate([[y], f.samples[:, 0], f.y])
        d = np.diff(ends, axis=0)[-1]
        change = float(np.max(np.abs(d - turn * np.round(d / np.where(turn > 0, turn, 1.0)))))
        y, done = f.y[0], done + k
    q, qd = consistent_state(system, y[:n], y[n:], 0.0, omega, params)
    return q, qd, done, change


def _segment_starts(system, omega, guess, q, qd, N, nu, params):
    """Full states (N, n) at the segment starts: from the PeriodicSolution guess, or by
    integrating one period from (q, qd)."""
    taus = 2 * np.pi * nu * np.arange(N) / N
    if isinstance(guess, PeriodicSolution) or N == 1:
        states = [start_state(system, guess if isinstance(guess, PeriodicSolution) else (q, qd), omega, params, tau / omega)
                  for tau in taus]
        return np.array([s[0] for s in states]), np.array([s[1] for s in states])
    f = flow(system, omega, np.concatenate([q, qd])[None], 0.0, 2 * np.pi * nu, params=params, rtol=1e-9, atol=1e-11,
             t_eval=taus)
    Y = np.array([np.concatenate(consistent_state(system, y[:system.n], y[system.n:], tau / omega, omega, params))
                  for y, tau in zip(f.samples[:, 0], taus)])
    return Y[:, :system.n], Y[:, system.n:]


def cyclic_indices(system, cyclic) -> list[int]:
    """Indices of the coordinates named or numbered in ``cyclic``."""
    out = []
    for c in cyclic:
        if isinstance(c, str):
            if c not in system.coordinate_names:
                raise InputError(f"cyclic coordinate {c!r} is not one of {system.coordinate_names}")
            out.append(system.coordinate_names.index(c))
        elif not 0 <= int(c) < system.n:
            raise InputError(f"cyclic coordinate index {c} is outside 0..{system.n - 1}")
        else:
            out.append(int(c))
    return out


@one_thread()  # small matrices: one BLAS/Numba thread (numerics.threads)
def shooting(system, omega: float, *, initial=None, params=None, options: ShootingOptions | None = None,
             **keywords) -> PeriodicSolution:
    """Periodic solution of ``system`` (a ``periodyn.DAE`` or an element model, solved as
    its non-linear equations ``element_dae``) at ``omega`` (rad/s) by single or multiple shooting.

    initial: PeriodicSolution (e.g. from ``ihb``), a full state (q, qd), or None (rest at
    ``system.q0``); params: model parameters (default the system's). options: a
    :class:`ShootingOptions` (subharmonic, settle_periods, segments, cyclic, tol, max_iter,
    samples, integration); keywords of those names, and of the :class:`IntegrationOptions`
    fields (integrator: "DOP853", an implicit "Radau"/"BDF" for stiff models with the analytic
    Jacobian, or "implicit" for element and rheo-linear models: ``steps`` trapezoidal steps per
    period in Numba with the exact monodromy of the discrete map,
    :mod:`periodyn.nonlinear.implicit`; rtol, atol, max_step, steps), override its fields. The
    result has spectra of q and lambda from ``samples`` points of the orbit and the monodromy
    multipliers (2(n - m),). Raises ConvergenceError saying what was tried when no start converges.
    """
    opts = shooting_options(options, keywords)
    system = as_dae(system, "shooting")
    if not np.isfinite(omega) or omega <= 0:
        raise InputError(f"omega must be a positive driving frequency in rad/s, got {omega!r}")
    integ, subharmonic, settle_periods = opts.integration, opts.subharmonic, opts.settle_periods
    P = system.parameters if params is None else params
    cyc = cyclic_indices(system, opts.cyclic)
    q, qd = start_state(system, initial, omega, P)
    if integ.integrator == "implicit":
        return implicit_shooting(system, omega, q, qd, subharmonic=subharmonic, steps=integ.steps,
                                 settle_periods=settle_periods or 0, tol=opts.tol, max_iter=opts.max_iter,
                                 samples=opts.samples, params=params)
    tried = []
    plans = [settle_periods] if settle_periods else [400] if initial is None else [0, 400]
    for periods in plans:
        if periods:
            q, qd, done, change = settle(system, omega, q, qd, periods=periods, subharmonic=subharmonic, params=P,
                                         cyclic=cyc)
            what = f"Newton after settling {done} periods (change per period {change:.3g})"
        else:
            what = "Newton from the start state"
        Q, QD = _segment_starts(system, omega, initial if not periods else None, q, qd, opts.segments, subharmonic, P)
        prob = ShootingProblem(system, Q, subharmonic, rtol=integ.rtol, atol=integ.atol, samples=opts.samples,
                               cyclic=cyc, method=integ.integrator, max_step=integ.max_step)
        try:
            res = prob.newton(prob.unknowns(Q, QD), float(omega), P, opts.tol, opts.max_iter)
        except (ConvergenceError, np.linalg.LinAlgError) as exc:
            last = (getattr(exc, "residual", float("nan")), getattr(exc, "iterations", 0))
            tried.append(f"{what}: residual {last[0]:.3g} after {last[1]} iterations")
            continue
        return prob.solution(res.x, omega, P, res.residual, res.iterations, prob.exponents(res.x, omega, P))
    raise ConvergenceError(f"shooting at omega={omega:.6g} rad/s found no periodic solution; tried: " + "; ".join(tried)
                           + ". Give initial= (an IHB solution or a nearby shooting solution), more settle_periods=, "
                           "segments= > 1 for a long or unstable period, or continue from a nearby omega with "
                           "continuation(..., method='shooting')", *last)
