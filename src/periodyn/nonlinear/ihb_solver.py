"""EGA-IHB: harmonic balance of ``M q'' + Phi_q^T lambda = f``, ``Phi = 0`` (Ju, Fan & Zhu 2021).

Unknowns X: real Fourier coefficients (``periodyn.nonlinear.ihb_fourier`` layout) of the n
coordinates and the m multipliers, coordinate-major: ``X[i*(2H+1) + r]``; size
``(n + m)(2H+1)``. Residual: Galerkin coefficients of
``r1 = M(q) q'' + Phi_q^T lambda - f(q, q', t)`` (n rows, N or N m) and ``r2 = Phi(q, t)``
(m rows, m or rad), evaluated by alternating frequency-time (App. A): coefficients ->
samples (pyFFTW) -> per-sample evaluation -> FFT.

Newton Jacobian (no finite differences): per-sample derivative matrices
``K = -df/dq + sum lam_k Phi_k,qq (+ d(M a)/dq)``, ``C = -df/dq'``, ``M``, ``Phi_q`` are
turned into (2H+1)x(2H+1) coefficient blocks by FFT (``product_blocks``) on a sparsity
pattern fixed at the first evaluation (``periodyn.nonlinear.ihb_jacobian``: dense blocks only for
entries that vary along the orbit, c I / c D / c D^2 for constant ones, a fill-reducing
ordering chosen once), factorised by SuperLU.

Sampling rule (anti-aliasing): the Jacobian blocks need the spectra of the sampled
matrices up to harmonic 2H, and a cubic term q^3 has 3H harmonics that must not fold
onto harmonics <= H. Both hold for ``p >= min_samples(H, 2H) = 6H + 1`` (product of a
series with H harmonics and coefficients with 2H harmonics); the default p is that
bound rounded up to an FFT-friendly size. Other non-linearities (sin, cos of angles) are
not band-limited: raise ``samples`` and check convergence in H.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..numerics.threads import one_thread
from ..errors import ConvergenceError, InputError
from .elements import as_dae
from ..numerics.newton_iteration import newton
from ..periodic import PeriodicSolution
from ..numerics.spectra import min_samples, sample_angles
from .ihb_fourier import complex_to_real, derivative_matrix, real_to_complex
from .ihb_jacobian import JacobianPattern, block_needs
from .options import IHBOptions, ihb_options
from .orbit_linearization import linearize_orbit, orbit_exponents
from ..stability.methods import flow_choice
from ..stability.orbit_flow import SampledGenerator, flow_exponents
from ..dae import DAE

__all__ = ["IHBProblem", "ihb", "default_samples"]

_DENSE_SIZE = 200  # unknowns up to which the Newton Jacobian is dense (IHBProblem)
_FORWARD_REL = 2.0 ** -26  # relative omega step of the force's forward difference (omega_derivative)


def default_samples(H: int) -> int:
    """Smallest 2^a 3^b >= min_samples(H, 2H) = 6H + 1 (see module docstring)."""
    need = min_samples(H, 2 * H)
    return min(v for v in (2 ** a * 3 ** b for a in range(20) for b in range(13)) if v >= need)


class IHBProblem:
    """Residual R(X) and Jacobian of the harmonic-balance equations of one DAE.

    harmonics H, samples p, subharmonic nu (orbit period nu 2 pi / omega); dense: the
    Jacobian as a dense array (default for at most ``_DENSE_SIZE`` unknowns: small problems,
    where the sparse pattern's bookkeeping costs more than the dense LU), else sparse.
    Samples and coefficients are related by the (p, 2H+1) real Fourier matrices (exact
    for p > 2H; the matrix products cost less than FFTs at the sizes of one orbit).
    """

    def __init__(self, system: DAE, harmonics: int, samples: int | None = None, subharmonic: int = 1,
                 dense: bool | None = None):
        if not isinstance(system, DAE):
            raise InputError(f"expected a periodyn.DAE, got {type(system).__name__}")
        if not isinstance(harmonics, (int, np.integer)) or harmonics < 1:
            raise InputError(f"harmonics must be a positive integer, got {harmonics!r}")
        self.system = system
        self.H = int(harmonics)
        self.p = int(samples) if samples is not None else default_samples(self.H)
        if self.p < 4 * self.H + 1:
            raise InputError(f"{self.p} samples are too few for {self.H} harmonics: the Jacobian needs the spectra "
                             f"up to harmonic {2 * self.H}; use samples >= {4 * self.H + 1} (default {default_samples(self.H)})")
        self.nu = int(subharmonic)
        self.n, self.m = system.n, system.m
        self.L = 2 * self.H + 1
        self.size = (self.n + self.m) * self.L
        self.D = derivative_matrix(self.H)
        self.theta = sample_angles(self.p)
        k = np.arange(1, self.H + 1)
        self._E = np.hstack([np.ones((self.p, 1)), np.cos(np.outer(self.theta, k)), np.sin(np.outer(self.theta, k))])
        self._ED, self._EDD = self._E @ self.D, self._E @ self.D @ self.D  # samples of d/dtau, d2/dtau2
        self._E3 = np.vstack([self._E, self._ED, self._EDD])  # all three in one product (time_samples)
        self._Pr = self._E.T * np.concatenate([[1.0], np.full(2 * self.H, 2.0)])[:, None] / self.p  # Galerkin
        self.dense = self.size <= _DENSE_SIZE if dense is None else bool(dense)
        M0 = system.mass(np.tile(np.asarray(system.q0, float), (self.p, 1)))
        self._mass = M0 if M0.strides[0] == 0 else None  # a constant mass: its (p, n, n) view, kept
        self._unit_mass = self._mass is not None and np.array_equal(M0[0], np.eye(self.n))
        self._last = None  # samples and df/dq' of the latest Jacobian evaluation (omega_derivative)
        self._pattern = None  # JacobianPattern of the sparse Newton Jacobian, built at its first evaluation

    # ------------------------------------------------------------------ layout
    def split(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """X -> (q coefficients (2H+1, n), lambda coefficients (2H+1, m)) real layout."""
        nq = self.n * self.L
        return X[:nq].reshape(self.n, self.L).T, X[nq:].reshape(self.m, self.L).T

    def join(self, Aq: np.ndarray, Al: np.ndarray) -> np.ndarray:
        return np.concatenate([Aq.T.ravel(), Al.T.ravel()])

    def initial(self, q0: np.ndarray | None = None, omega: float = 1.0, params=None) -> np.ndarray:
        """Constant guess q = q0 (default ``system.q0``) and the static multipliers
        ``Phi_q^T lambda = mean_t f(q0, 0, t)`` (least squares), so that gravity
        stiffness ``lambda Phi_qq`` is present from the first Newton step."""
        s = self.system
        P = s.parameters if params is None else params
        q = np.array(s.q0 if q0 is None else q0, float)
        Aq = np.zeros((self.L, self.n))
        Aq[0] = q
        Al = np.zeros((self.L, self.m))
        if self.m:
            t = self.theta / omega
            Q = np.broadcast_to(q, (self.p, self.n))
            fbar = s.force(Q, np.zeros_like(Q), t, omega, P).mean(axis=0)
            Pq = s.constraint_jacobian(Q[:1], t[:1], omega, P)[0]
            Al[0] = np.linalg.lstsq(Pq.T, fbar, rcond=None)[0]
        return self.join(Aq, Al)

    def from_solution(self, sol: PeriodicSolution) -> np.ndarray:
        """Unknowns from a PeriodicSolution (re-truncated or zero-padded to H, same nu)."""
        if sol.subharmonic != self.nu:
            raise InputError(f"solution has subharmonic {sol.subharmonic}, problem {self.nu}")
        Hs = (sol.harmonics.shape[0] - 1) // 2
        pad = max(0, self.H - Hs)
        lam = sol.lambda_harmonics if sol.lambda_harmonics is not None else np.zeros((2 * Hs + 1, self.m))
        cq, cl = (np.pad(c, ((pad, pad), (0, 0))) if pad else c for c in (sol.harmonics, lam))
        return self.join(complex_to_real(cq, self.H), complex_to_real(cl, self.H))

    # ------------------------------------------------------------------ AFT
    def time_samples(self, X: np.ndarray, omega: float):
        """Samples over one orbit: t (p,), q, q', q'' (p, n), lambda (p, m)."""
        Om, p = omega / self.nu, self.p
        Aq, Al = self.split(X)
        lam = self._E @ Al if self.m else np.zeros((p, 0))
        S = self._E3 @ Aq
        return self.theta / Om, S[:p], Om * S[p:2 * p], Om ** 2 * S[2 * p:], lam

    def residual(self, X: np.ndarray, omega: float, params=None) -> np.ndarray:
        """R(X), shape (size,)."""
        return self._evaluate(X, omega, params, jacobian=False)[0]

    def residual_jacobian(self, X: np.ndarray, omega: float, params=None):
        """(R (size,), J sparse csc (size, size))."""
        return self._evaluate(X, omega, params, jacobian=True)

    def omega_derivative(self, X: np.ndarray, omega: float, h: float, params=None) -> np.ndarray:
        """dR/domega at X (size,) for the continuation's bordered rows: the central difference
        (R(X, omega + h) - R(X, omega - h)) / 2h with the samples of X taken once (q', q''
        scale with omega) and one projection; right after the Jacobian at the same point of an
        unconstrained system, the chain rule through q', q'' with its df/dq', and the force's
        explicit dependence on t and omega alone by the forward difference (step
        ``_FORWARD_REL`` |omega|, near sqrt(eps): one force call) from the residual's own force samples."""
        P = self.system.parameters if params is None else params
        p, nu, last = self.p, self.nu, self._at_last(X, omega, P)
        if not self.m and last is not None:  # the Jacobian's samples at this point: q fixed, q', q'' scale with
            q, qd, qdd, M, Cf, f = last[4:8] + last[9:]  # omega (d/domega: q'/omega, 2 q''/omega)
            w1 = omega + _FORWARD_REL * max(abs(omega), 1e-3)
            f1 = self.system.force(q, qd, self.theta / (w1 / nu), w1, P)
            Ma = qdd @ M[0].T if M.strides[0] == 0 else np.matmul(M, qdd[:, :, None])[:, :, 0]
            d1 = (2.0 * Ma - np.matmul(Cf, qd[:, :, None])[:, :, 0]) / omega - (f1 - f) / (w1 - omega)
            return self.join(self._Pr @ d1, np.zeros((self.L, 0)))
        Aq, Al = self.split(X)
        S = self._E3 @ Aq
        lam = self._E @ Al if self.m else np.zeros((p, 0))
        (a1, a2), (b1, b2) = (self._sampled(self.theta / (w / nu), S[:p], (w / nu) * S[p:2 * p],
                                            (w / nu) ** 2 * S[2 * p:], lam, w, P)[:2] for w in (omega + h, omega - h))
        return self.join(self._Pr @ ((a1 - b1) / (2 * h)), self._Pr @ ((a2 - b2) / (2 * h)))

    def _at_last(self, X, omega, P):
        """The latest Jacobian evaluation's samples if it was at (X, omega, P), else None."""
        last = self._last
        return last if last is not None and last[1] == omega and last[2] == P and (last[0] == X).all() else None

    def sampled_residual(self, X: np.ndarray, omega: float, params=None):
        """The DAE residual at the p sample times, before projection: (t (p,), r1 =
        M q'' + Phi_q^T lambda - f (p, n) in N or N m, r2 = Phi (p, m) in m or rad, f (p, n))."""
        P = self.system.parameters if params is None else params
        t, q, qd, qdd, lam = self.time_samples(X, omega)
        r1, r2, f = self._sampled(t, q, qd, qdd, lam, omega, P)[:3]
        return t, r1, r2, f

    def _sampled(self, t, q, qd, qdd, lam, omega, P):
        """(r1, r2, f, M, Phi_q) at the samples (r2, Phi_q empty without constraints)."""
        sysm = self.system
        M = self._mass if self._mass is not None and len(q) == self.p else sysm.mass(q)
        Ma = qdd @ M[0].T if M.strides[0] == 0 else np.matmul(M, qdd[:, :, None])[:, :, 0]  # constant M: one product
        f = sysm.force(q, qd, t, omega, P)
        r1 = Ma - f
        if not self.m:
            return r1, np.zeros((len(t), 0)), f, M, None
        Pq = sysm.constraint_jacobian(q, t, omega, P)
        r1 += np.matmul(lam[:, None, :], Pq)[:, 0]
        return r1, sysm.constraint(q, t, omega, P), f, M, Pq

    def _evaluate(self, X, omega, params, jacobian):
        sysm = self.system
        P = sysm.parameters if params is None else params
        t, q, qd, qdd, lam = self.time_samples(X, omega)
        r1, r2, f, M, Pq = self._sampled(t, q, qd, qdd, lam, omega, P)
        R = self.join(self._Pr @ r1, self._Pr @ r2 if self.m else np.zeros((self.L, 0)))
        if not jacobian:
            return R, None
        Kf, Cf = sysm.force_jacobians(q, qd, t, omega, P)
        self._last = (X.copy(), omega, P, t, q, qd, qdd, M, Kf, Cf, f)  # omega_derivative, state_generator there
        Kt = -Kf  # a new array: the terms below are added in place (one pass each over (p, n, n))
        if self.m:
            Kt += sysm.constraint_hessian(q, lam, t, omega, P)
        if sysm.mass_jacobian is not None:
            Kt += sysm.mass_jacobian(q, qdd)
        Ct = -Cf
        return R, (self._dense(Kt, Ct, M, Pq, omega) if self.dense else self._assemble(Kt, Ct, M, Pq, omega))

    def _dense(self, Kt, Ct, M, Pq, omega):
        """Dense Jacobian: block (i, j) of the coordinates is Pr diag(K_ij) E + Om Pr diag(C_ij) E D
        + Om^2 Pr diag(M_ij) E D^2, the multiplier blocks Pr diag(Phi_q) E (Galerkin of the samples)."""
        Om, p, n, m, L = omega / self.nu, self.p, self.n, self.m, self.L
        T = (Kt.reshape(p, n * n, 1) * self._E[:, None] + Om * Ct.reshape(p, n * n, 1) * self._ED[:, None]
             + Om ** 2 * np.asarray(M).reshape(p, n * n, 1) * self._EDD[:, None])
        Jqq = (self._Pr @ T.reshape(p, -1)).reshape(L, n, n, L).transpose(1, 0, 2, 3).reshape(n * L, n * L)
        if not m:
            return Jqq
        G = self._Pr @ (Pq.reshape(p, m * n, 1) * self._E[:, None]).reshape(p, -1)
        G = G.reshape(L, m, n, L).transpose(1, 0, 2, 3).reshape(m * L, n * L)  # rows of Phi: (c, k), (j, l)
        Jp = np.asarray(G.reshape(m, L, n, L).transpose(2, 1, 0, 3).reshape(n * L, m * L))  # (j, k), (c, l)
        return np.block([[Jqq, Jp], [G, np.zeros((m * L, m * L))]])

    def _assemble(self, Kt, Ct, M, Pq, omega):
        """Sparse Jacobian on the problem's fixed pattern (``periodyn.nonlinear.ihb_jacobian``), rebuilt
        (larger) only when an evaluation needs a block or a harmonic band outside it."""
        if Pq is None:
            Pq = np.zeros((Kt.shape[0], 0, self.n))
        need, varying, constants, spectra = block_needs(Kt, Ct, M, Pq, self.H)
        pat = self._pattern
        if pat is None or not pat.fits(need):
            pat = self._pattern = (JacobianPattern(self.H, self.n, self.m, need) if pat is None else
                                   JacobianPattern(self.H, self.n, self.m, pat.widened(need), pat.ordering.method))
        return pat.assemble(omega / self.nu, varying, constants, spectra)

    # ------------------------------------------------------------------ results
    def linearization(self, X, omega, params=None):
        """The orbit's perturbation equations (``periodyn.nonlinear.orbit_linearization.OrbitLinearization``)."""
        t, q, qd, qdd, lam = self.time_samples(X, omega)
        return linearize_orbit(self.system, t, q, qd, qdd, lam, omega, params, 2 * np.pi * self.nu / omega)

    def state_generator(self, X, omega, params=None) -> SampledGenerator:
        """State matrices A (p, 2n, 2n) (1/s) of the perturbation y' = A y, y = (dq, dq'), of
        the unconstrained orbit X at its sample times, as a SampledGenerator (the entries that
        vary along the orbit): dq'' = M^-1 (df/dq - d(M q'')/dq) dq + M^-1 df/dq' dq'."""
        P = self.system.parameters if params is None else params
        sysm, n, last = self.system, self.n, self._at_last(X, omega, P)
        if last is not None:  # the corrector's last Jacobian was at this orbit
            t, q, qd, qdd, M, Kf, Cf = last[3:10]
        else:
            t, q, qd, qdd, _ = self.time_samples(X, omega)
            M, (Kf, Cf) = sysm.mass(q), sysm.force_jacobians(q, qd, t, omega, P)
        if sysm.mass_jacobian is not None:
            Kf = Kf - sysm.mass_jacobian(q, qdd)
        if M.strides[0] != 0 or M is not self._mass or not self._unit_mass:  # M^-1 [Kf, Cf] (p, n, 2n)
            J = np.concatenate([Kf, Cf], axis=2)
            J = (np.linalg.solve(M, J) if M.strides[0] else  # a constant mass: one factorization for every sample
                 np.linalg.solve(M[0], J.transpose(1, 0, 2).reshape(n, -1)).reshape(n, self.p, 2 * n).transpose(1, 0, 2))
            Kf, Cf = J[:, :, :n], J[:, :, n:]
        return SampledGenerator.from_blocks(Kf, Cf)

    def exponents(self, X, omega, params=None, method="magnus"):
        """Floquet exponents of the orbit X (FloquetExponents at omega, subharmonic nu).
        method "auto" on an unconstrained orbit not too stiff by the registry's rule
        (:func:`periodyn.stability.methods.flow_choice`) takes the certified Magnus flow of
        its samples (:mod:`periodyn.stability.orbit_flow`), and the linearized orbit's
        "auto" where that does not certify."""
        if method == "auto" and not self.m:
            A = self.state_generator(X, omega, params)
            use, why = flow_choice(A.stiffness(omega, self.nu))
            exps = flow_exponents(A, omega, self.nu, why) if use else None
            if exps is not None:
                return exps
        exps = orbit_exponents(self.linearization(X, omega, params), method)
        return replace(exps, omega=float(omega), subharmonic=self.nu)

    def solution(self, X, omega, params, residual, iterations, stability=None) -> PeriodicSolution:
        """The PeriodicSolution of unknowns X (the real layout ends here: two-sided harmonics)."""
        Aq, Al = self.split(X)
        s = self.system
        return PeriodicSolution(float(omega), real_to_complex(Aq), None, s.coordinate_names, s.coordinate_names,
                                float(residual), iterations=int(iterations), method="ihb", subharmonic=self.nu,
                                lambda_harmonics=real_to_complex(Al), constraint_names=s.constraint_names,
                                stability=stability, parameters=dict(s.parameters if params is None else params))

    def newton(self, X, omega, params=None, tol=1e-8, max_iter=30):
        """Newton with backtracking on the residual max-norm; returns a NewtonResult or raises
        ConvergenceError."""
        return newton(lambda Y: self.residual_jacobian(Y, omega, params), X, tol=tol, max_iter=max_iter,
                      residual=lambda Y: self.residual(Y, omega, params), backtrack=6,
                      label=f"IHB Newton at omega={omega:.6g} rad/s",
                      hint="give a better initial guess (continuation) or more harmonics")


@one_thread()  # small matrices: one BLAS/Numba thread (numerics.threads)
def ihb(system, omega: float, harmonics: int = 5, *, initial=None, params=None, options: IHBOptions | None = None,
        **keywords) -> PeriodicSolution:
    """Periodic solution of ``system`` (a ``periodyn.DAE`` or an element model, solved as
    its non-linear equations ``element_dae``) driven at ``omega`` (rad/s) by EGA-IHB.

    harmonics: H; initial: a PeriodicSolution, a real-layout unknown vector, a (n,) constant
    configuration or None (``system.q0``); params: model parameters (default the system's).
    options: an :class:`IHBOptions` (samples p, default see module docstring; subharmonic nu,
    orbit period nu 2 pi / omega; tol, residual max-norm in N, N m, m, rad; max_iter;
    stability, a stability method or None); keywords of those names override its fields.
    Raises ConvergenceError when Newton fails.
    """
    opts = ihb_options(options, keywords)
    tol, max_iter, stability = opts.tol, opts.max_iter, opts.stability
    system = as_dae(system, "ihb")
    if not np.isfinite(omega) or omega <= 0:
        raise InputError(f"omega must be a positive driving frequency in rad/s, got {omega!r}")
    prob = IHBProblem(system, harmonics, opts.samples, opts.subharmonic)
    if initial is None:
        X0 = prob.initial(omega=float(omega), params=params)
        try:
            res = prob.newton(X0, float(omega), params, tol, max_iter)
        except ConvergenceError as exc:
            res = _stepped_start(prob, float(omega), params, tol, max_iter, exc)
        exps = None if stability is None else prob.exponents(res.x, float(omega), params, stability)
        return prob.solution(res.x, omega, params, res.residual, res.iterations, exps)
    if isinstance(initial, PeriodicSolution):
        X0 = prob.from_solution(initial)
    else:
        a = np.asarray(initial, float)
        X0 = prob.initial(a, float(omega), params) if a.shape == (system.n,) else a
        if X0.shape != (prob.size,):
            raise InputError(f"initial must be a PeriodicSolution, an (n,)={system.n} configuration or a vector of "
                             f"{prob.size} unknowns, got shape {a.shape}")
    res = prob.newton(X0, float(omega), params, tol, max_iter)
    exps = None if stability is None else prob.exponents(res.x, float(omega), params, stability)
    return prob.solution(res.x, omega, params, res.residual, res.iterations, exps)


_EASY_HALVINGS = 6  # start speeds tried: omega / 2, omega / 4, ... omega / 64
_FIRST_RATIO, _MAX_RATIO, _MIN_RATIO = 1.25, 2.0, 1.0 + 1e-4  # speed ratios of the stepping


def _stepped_start(prob: IHBProblem, omega: float, params, tol: float, max_iter: int, first: ConvergenceError):
    """Default start when Newton from the static configuration fails at ``omega``: the same
    start at a lower speed (omega/2, omega/4, ...: slower driving is closer to static), then
    steps up in speed to ``omega``, each Newton from the secant prediction of the last two
    orbits, the speed ratio growing after easy steps and halving (in log omega) after a
    failure. Raises ConvergenceError saying what was tried and what to change."""
    tried = [f"Newton from the static configuration at {omega:.6g} rad/s (residual {first.residual:.3g} after "
             f"{first.iterations} iterations)"]
    w, X = omega, None
    for _ in range(_EASY_HALVINGS):
        w *= 0.5
        try:
            X = prob.newton(prob.initial(omega=w, params=params), w, params, tol, max_iter).x
            break
        except ConvergenceError:
            continue
    if X is None:
        tried.append(f"the same start at {omega / 2:.6g} .. {w:.6g} rad/s (halving the speed)")
        raise ConvergenceError(f"IHB start failed at omega={omega:.6g} rad/s; tried: " + "; ".join(tried) +
                               ". Pass initial= a solution at a nearby speed (periodyn.continuation from a speed "
                               "where the orbit is known), or a configuration close to the orbit's mean",
                               first.residual, first.iterations)
    tried.append(f"a converged start at {w:.6g} rad/s")
    path = [(np.log(w), X)]
    ratio = _FIRST_RATIO
    while w < omega:
        w_new = min(w * ratio, omega)
        if len(path) > 1:  # secant in log omega
            (l0, X0), (l1, X1) = path[-2], path[-1]
            guess = X1 + (X1 - X0) * (np.log(w_new) - l1) / (l1 - l0)
        else:
            guess = X
        try:
            res = prob.newton(guess, w_new, params, tol, max_iter)
        except ConvergenceError as exc:
            ratio = np.sqrt(ratio)
            if ratio < _MIN_RATIO:
                tried.append(f"stepping up in speed from there, stopped at {w:.6g} rad/s (no step above a ratio "
                             f"{_MIN_RATIO:g} converged: residual {exc.residual:.3g}; a fold or a bifurcation of "
                             f"the orbit family may lie between {w:.6g} and {omega:.6g} rad/s)")
                raise ConvergenceError(f"IHB start failed at omega={omega:.6g} rad/s; tried: " + "; ".join(tried) +
                                       ". Follow the branch with periodyn.continuation(system, "
                                       f"({w:.6g}, {omega:.6g}), ...) (it passes folds) and start from its solution",
                                       exc.residual, exc.iterations) from None
            continue
        w, X = w_new, res.x
        path.append((np.log(w), X))
        ratio = min(ratio ** (1.5 if res.iterations <= 4 else 1.0), _MAX_RATIO)
    return res
