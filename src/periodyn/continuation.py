"""Pseudo-arc-length continuation of ``R(X, p) = 0`` and the user-facing ``continuation``.

The generic driver :func:`pseudo_arclength` only sees a *problem* object with
``residual_jacobian(X, omega, params) -> (R, J)`` (J sparse or dense),
``parameter_derivative(X, omega, params, name) -> dR/dp`` and an optional ``monitor``
callback returning Floquet multipliers; IHB (``periodyn.dae.ihb.IHBProblem``) and
shooting (``periodyn.nonlinear.shooting.ShootingProblem``) plug into it unchanged.

Scaling: unknowns are compared in the weighted norm
``|dX|^2 = sum_i (dX_i / s_i)^2 / N + (dp / s_p)^2`` with per-group scales s (RMS of the
group at the first point, e.g. displacement coefficients vs multiplier coefficients) and
s_p = |p_0|, so that coefficients (m, rad), multipliers (N) and the parameter weigh alike.
Steps: tangent predictor, Newton corrector on the bordered system (R = 0 plus the
hyperplane through the predictor orthogonal to the tangent); ds grows x1.5 after an
easy step (<= 3 iterations), shrinks after a hard one, halves after a failed step
(recovery) down to ds_min, and a step that turns the tangent by more than ~25 degrees is
retried shorter. Folds: sign change of dp/ds, located by the Illinois method on the
arc between the two points (zero of dp/ds, each trial solved by the corrector); period doubling / Neimark-Sacker: a
multiplier leaving the unit circle through -1 / as a complex pair (linear interpolation
of |mu| - 1 between the two points).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
import scipy.sparse as sp
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from .errors import ConvergenceError, InputError

__all__ = ["SpecialPoint", "Branch", "pseudo_arclength", "continuation", "switch_period_doubling"]


@dataclass(frozen=True)
class SpecialPoint:
    """A bifurcation between branch points ``index`` and ``index + 1``.

    type: "fold", "period-doubling" or "neimark-sacker"; omega (rad/s) and parameter value
    estimated by linear interpolation; multiplier: the critical multiplier (nan for folds
    found from dp/ds only)."""

    type: str
    index: int
    omega: float
    parameter: float
    multiplier: complex = complex("nan")


@dataclass(frozen=True, eq=False)
class Branch:
    """Columnar continuation result (k points).

    omega (k,) rad/s; parameter (k,) values of the continued parameter (== omega for
    omega continuation); parameter_name (None for omega); amplitude (k, n) half
    peak-to-peak per coordinate; stable (k,) bool (or None entries without stability);
    max_multiplier (k,); residual (k,) and iterations (k,) of each corrector;
    special_points; solutions: the PeriodicSolution of every point; status: why the
    branch ended; problem and options: what produced it.
    """

    omega: np.ndarray
    parameter: np.ndarray
    parameter_name: str | None
    amplitude: np.ndarray
    stable: np.ndarray
    max_multiplier: np.ndarray
    residual: np.ndarray
    iterations: np.ndarray
    special_points: tuple[SpecialPoint, ...]
    solutions: tuple
    status: str
    problem: Any = field(repr=False, default=None)
    options: dict = field(default_factory=dict)
    unknowns: np.ndarray | None = field(repr=False, default=None)

    def __len__(self) -> int:
        return len(self.omega)

    def points(self, type: str) -> list[SpecialPoint]:
        """Special points of one type."""
        return [s for s in self.special_points if s.type == type]


def _factor(J):
    """Solver callable for J (sparse: SuperLU, dense: LAPACK LU)."""
    if sp.issparse(J):
        return spla.splu(sp.csc_matrix(J)).solve
    lu = sla.lu_factor(J)
    return lambda b: sla.lu_solve(lu, b)


def _solve_bordered(solve, Rp, row_x, row_p, r_x, r_p):
    """Solve [[J, Rp], [row_x^T, row_p]] [x; y] = [r_x; r_p] by block elimination
    (two solves with the factorization of J; keeps the sparse structure of J)."""
    a = solve(r_x)
    b = solve(Rp)
    y = (r_p - row_x @ a) / (row_p - row_x @ b)
    return np.concatenate([a - b * y, [y]])


def pseudo_arclength(problem, X0: np.ndarray, p0: float, p_stop: float, *, set_parameter: Callable,
                     parameter_name: str | None, scales: np.ndarray, tangent=None, ds: float = 0.02,
                     ds_min: float = 1e-5, ds_max: float = 0.2, max_points: int = 400, tol: float = 1e-8,
                     max_iter: int = 8, monitor: Callable | None = None, make_solution: Callable | None = None,
                     problem_omega: Callable | None = None):
    """Continue the solution X0 of ``R(X, p0) = 0`` until p passes ``p_stop``.

    set_parameter(p) -> (omega, params) maps the continuation parameter to the problem
    arguments; scales (N,) per-unknown scales; tangent: optional initial (dX, dp) direction
    (branch switching), otherwise the tangent toward p_stop. monitor(X, omega, params) ->
    multipliers; make_solution(X, omega, params, residual, iterations, multipliers).
    Returns a Branch (problem-agnostic fields only).
    """
    N = len(X0)
    w = 1.0 / (scales ** 2 * N)
    sp_ = max(abs(p0), 1e-6)
    wp = 1.0 / sp_ ** 2
    direction = np.sign(p_stop - p0) or 1.0

    def norm(t):
        return np.sqrt(np.sum(w * t[:N] ** 2) + wp * t[N] ** 2)

    def evaluate(X, p):
        om, P = set_parameter(p)
        R, J = problem.residual_jacobian(X, om, P)
        return R, J, problem.parameter_derivative(X, om, P, parameter_name)

    def tangent_at(J, Rp, t_old, solve=None):
        t = _solve_bordered(solve or _factor(J), Rp, w * t_old[:N], wp * t_old[N], np.zeros(N), 1.0)
        t /= norm(t)
        if np.sum(w * t[:N] * t_old[:N]) + wp * t[N] * t_old[N] < 0:
            t = -t
        return t

    X, p = np.array(X0, float), float(p0)
    R, J, Rp = evaluate(X, p)
    r0 = float(np.max(np.abs(R)))
    if r0 > tol:
        raise InputError(f"the start point is not a solution (residual {r0:.3g} > {tol:.1g}); converge it first")
    if tangent is None:
        t_old = np.zeros(N + 1)
        t_old[N] = direction
        t = tangent_at(J, Rp, t_old)
        if t[N] * direction < 0:
            t = -t
    else:
        t = np.asarray(tangent, float) / norm(np.asarray(tangent, float))

    def corrector(Xp, pp, tt):
        """Newton on R = 0 and the hyperplane through (Xp, pp) normal to tt; returns the
        point and the tangent there, or None."""
        Xc, pc = Xp.copy(), pp
        for _ in range(max_iter):
            R, J, Rp = evaluate(Xc, pc)
            g = np.sum(w * tt[:N] * (Xc - Xp)) + wp * tt[N] * (pc - pp)
            if float(np.max(np.abs(R))) <= tol and abs(g) <= 1e-10:
                return Xc, pc, tangent_at(J, Rp, tt)
            d = _solve_bordered(_factor(J), Rp, w * tt[:N], wp * tt[N], -R, -g)
            Xc, pc = Xc + d[:N], pc + d[N]
        return None

    def refine_fold(Xa, pa, ta, Xb, pb):
        """Fold between two points: zero of dp/ds along the arc, by the Illinois method on
        the arc-length fraction sigma (each trial point solved by the corrector)."""
        L = norm(np.concatenate([Xb - Xa, [pb - pa]]))
        sa, fa, sb, fb = 0.0, ta[N], 1.0, None
        res = corrector(Xa + L * ta[:N], pa + L * ta[N], ta)
        if res is None:
            return None
        fb = res[2][N]
        if np.sign(fa) == np.sign(fb):
            return None
        side, best = 0, res[1]
        for _ in range(40):
            sg = sa + fa * (sb - sa) / (fa - fb)
            res = corrector(Xa + sg * L * ta[:N], pa + sg * L * ta[N], ta)
            if res is None:
                return None
            fg, best = res[2][N], res[1]
            if abs(fg) < 1e-10 or abs(sb - sa) < 1e-12:
                break
            if np.sign(fg) == np.sign(fa):
                sa, fa = sg, fg
                if side == -1:
                    fb *= 0.5
                side = -1
            else:
                sb, fb = sg, fg
                if side == 1:
                    fa *= 0.5
                side = 1
        return float(best)

    def record(X, p, rn, it):
        om, P = set_parameter(p)
        mu = monitor(X, om, P) if monitor is not None else None
        return mu, make_solution(X, om, P, rn, it, mu)

    mu, sol = record(X, p, r0, 0)
    Xs, ps, sols, mus, res, its, tps = [X.copy()], [p], [sol], [mu], [r0], [0], [t[N]]
    specials: list[SpecialPoint] = []
    status = "max_points reached"
    while len(ps) < max_points:
        if (p - p_stop) * direction >= 0 and len(ps) > 1:
            status = "parameter range covered"
            break
        accepted = False
        while ds >= ds_min:
            Xp, pp = X + ds * t[:N], p + ds * t[N]
            Xc, pc = Xp.copy(), pp
            ok = False
            for it in range(1, max_iter + 1):
                try:
                    R, J, Rp = evaluate(Xc, pc)
                except (ConvergenceError, np.linalg.LinAlgError, FloatingPointError, ValueError):
                    break
                rn = float(np.max(np.abs(R)))
                if not np.isfinite(rn):
                    break
                g = np.sum(w * t[:N] * (Xc - Xp)) + wp * t[N] * (pc - pp)
                if rn <= tol and abs(g) <= 1e-10:
                    ok = True
                    break
                try:
                    solve = _factor(J)
                    d = _solve_bordered(solve, Rp, w * t[:N], wp * t[N], -R, -g)
                except (RuntimeError, np.linalg.LinAlgError, ValueError):
                    break
                if not np.all(np.isfinite(d)):
                    break
                Xc, pc = Xc + d[:N], pc + d[N]
            if ok:
                t_new = tangent_at(J, Rp, t, solve if it > 1 else None)
                cos = np.sum(w * t_new[:N] * t[:N]) + wp * t_new[N] * t[N]
                if cos < 0.9 and ds > ds_min * 2:
                    ds *= 0.5
                    continue
                accepted = True
                break
            ds *= 0.5
        if not accepted:
            status = f"step size below ds_min={ds_min:g} at parameter {p:.6g}: corrector failed (possible branch point)"
            break
        X_old, p_old, t_old_p, t_prev = X, p, t[N], t
        X, p, t = Xc, pc, t_new
        mu, sol = record(X, p, rn, it - 1)
        Xs.append(X.copy()), ps.append(p), sols.append(sol), mus.append(mu), res.append(rn), its.append(it - 1), tps.append(t[N])
        k = len(ps) - 2
        om_old, om_new = set_parameter(p_old)[0], set_parameter(p)[0]
        if np.sign(t_old_p) != np.sign(t[N]) and t_old_p != 0:
            pf = refine_fold(X_old, p_old, t_prev, X, p)
            if pf is None:
                pf = _fold_parameter(Xs[-3:], ps[-3:], norm) if k >= 1 else 0.5 * (p_old + p)
            omf = pf if parameter_name is None else om_new
            specials.append(SpecialPoint("fold", k, float(omf), float(pf)))
        if mu is not None and mus[-2] is not None:
            for sp_pt in _multiplier_crossings(mus[-2], mu, k, p_old, p, om_old, om_new):
                pr = _refine_crossing(problem, monitor, set_parameter, parameter_name, Xs[-2], p_old, X, p, tol)
                if pr is not None:
                    sp_pt = SpecialPoint(sp_pt.type, k, float(set_parameter(pr[0])[0]), float(pr[0]), complex(pr[1]))
                specials.append(sp_pt)
        if it - 1 <= 3:
            ds = min(ds * 1.5, ds_max)
        elif it - 1 >= 6:
            ds *= 0.7
    return Xs, ps, sols, mus, res, its, specials, status


def _fold_parameter(Xs, ps, norm) -> float:
    """Fold location: vertex of the parabola p(s) through three points (s = arc length)."""
    s1 = norm(np.concatenate([Xs[1] - Xs[0], [ps[1] - ps[0]]]))
    s2 = s1 + norm(np.concatenate([Xs[2] - Xs[1], [ps[2] - ps[1]]]))
    a, b, c = np.polyfit([0.0, s1, s2], ps, 2)
    if a == 0:
        return float(ps[1])
    s = min(max(-b / (2 * a), 0.0), s2)
    return float(np.polyval([a, b, c], s))


def _newton(problem, X, om, P, tol, max_iter=12):
    for _ in range(max_iter):
        R, J = problem.residual_jacobian(X, om, P)
        if np.max(np.abs(R)) <= tol:
            return X
        X = X - _factor(J)(R)
    return None


def _refine_crossing(problem, monitor, set_parameter, name, Xa, pa, Xb, pb, tol, max_iter=30):
    """Parameter where the largest |mu| crosses 1 between two branch points, by the
    Illinois (modified regula falsi) method on g(p) = max|mu| - 1 with fixed-parameter
    Newton solves; returns (p, critical multiplier) or None if a solve fails."""
    def g(X, p):
        om, P = set_parameter(p)
        mu = monitor(X, om, P)
        j = int(np.argmax(np.abs(mu)))
        return float(np.abs(mu[j]) - 1.0), mu[j]

    ga, _ = g(Xa, pa)
    gb, mub = g(Xb, pb)
    side = 0
    mu = mub
    for _ in range(max_iter):
        s = ga / (ga - gb) if ga != gb else 0.5
        p = pa + s * (pb - pa)
        om, P = set_parameter(p)
        X = _newton(problem, Xa + s * (Xb - Xa), om, P, tol)
        if X is None:
            return None
        gp, mu = g(X, p)
        if abs(gp) < 1e-9 or abs(pb - pa) < 1e-12 * max(1.0, abs(p)):
            return p, mu
        if np.sign(gp) == np.sign(ga):
            Xa, pa, ga = X, p, gp
            if side == -1:
                gb *= 0.5
            side = -1
        else:
            Xb, pb, gb = X, p, gp
            if side == 1:
                ga *= 0.5
            side = 1
    return p, mu


def _multiplier_crossings(mu_a, mu_b, k, pa, pb, oa, ob) -> list[SpecialPoint]:
    """Period-doubling / Neimark-Sacker crossings between two points (folds come from dp/ds)."""
    out = []
    na, nb = int(np.sum(np.abs(mu_a) > 1)), int(np.sum(np.abs(mu_b) > 1))
    if na == nb:
        return out
    crit_side = mu_b if nb > na else mu_a
    other = mu_a if nb > na else mu_b
    outside = crit_side[np.abs(crit_side) > 1]
    for c in outside:
        # the multiplier of the other side that continues c
        j = int(np.argmin(np.abs(other - c)))
        c2 = other[j]
        if abs(c2) > 1:
            continue
        if abs(c.imag) > 1e-6 * abs(c) and abs(c2.imag) > 1e-6 * abs(c2):
            typ = "neimark-sacker"
        elif c.real < 0:
            typ = "period-doubling"
        else:
            continue  # real multiplier through +1: a fold, reported from dp/ds
        fa, fb = (abs(c2) - 1, abs(c) - 1) if nb > na else (abs(c) - 1, abs(c2) - 1)
        s = fa / (fa - fb) if fa != fb else 0.5
        out.append(SpecialPoint(typ, k, float(oa + s * (ob - oa)), float(pa + s * (pb - pa)), complex(c)))
        if typ == "neimark-sacker":
            break  # one entry per complex pair
    return out


def _group_scales(problem, X0: np.ndarray) -> np.ndarray:
    """Per-unknown scales: RMS of the q-coefficient group and of the multiplier group."""
    groups = getattr(problem, "groups", None)
    s = np.empty_like(X0)
    if groups is None:
        groups = [np.arange(len(X0))]
    ref = max(np.sqrt(np.mean(X0 ** 2)), 1e-12)
    for g in groups:
        if len(g):
            s[g] = max(np.sqrt(np.mean(X0[g] ** 2)), 1e-6 * ref, 1e-12)
    return s


def continuation(system, omega, harmonics: int = 5, method: str = "ihb", parameter: tuple | None = None, *,
                 initial=None, samples: int | None = None, subharmonic: int = 1, stability: str | None = "monodromy",
                 ds: float = 0.02, ds_min: float = 1e-5, ds_max: float = 0.2, max_points: int = 400,
                 tol: float | None = None, tangent=None, shooting_samples: int = 128) -> Branch:
    """Response curve of a ``periodyn.DAE`` by pseudo-arc-length continuation.

    omega: (start, stop) rad/s for a frequency response, or a fixed value when
    ``parameter=(name, start, stop)`` continues a named parameter (forcing or base
    amplitude). method: "ihb" (harmonics H, samples p) or "shooting". initial: a
    PeriodicSolution at the start (else solved from ``system.q0``). stability:
    "monodromy", "hill" or None (IHB); shooting always has its monodromy multipliers.
    tangent: initial (dX, dp) for branch switching. Every point carries its residual and
    Newton iterations; non-converged points are never recorded.
    """
    from .dae.ihb import IHBProblem
    from .dae.model import DAE
    from .dae.stability import ihb_multipliers
    from .nonlinear.shooting import ShootingProblem

    if not isinstance(system, DAE):
        raise InputError(f"continuation expects a periodyn.DAE, got {type(system).__name__}")
    if parameter is None:
        try:
            p0, p1 = (float(v) for v in omega)
        except TypeError:
            raise InputError("omega must be (start, stop) in rad/s, or give parameter=(name, start, stop)") from None
        name, om_fixed = None, None
    else:
        if len(parameter) != 3 or parameter[0] not in system.parameters:
            raise InputError(f"parameter must be (name, start, stop) with name in {sorted(system.parameters)}")
        name, p0, p1 = parameter[0], float(parameter[1]), float(parameter[2])
        om_fixed = float(omega)

    def set_parameter(p):
        if name is None:
            return p, system.parameters
        return om_fixed, dict(system.parameters, **{name: p})

    om0, P0 = set_parameter(p0)
    if method == "ihb":
        prob = IHBProblem(system, harmonics, samples, subharmonic)
        prob.groups = [np.arange(system.n * prob.L), np.arange(system.n * prob.L, prob.size)]
        tol = 1e-8 if tol is None else tol
        X0 = prob.from_solution(initial) if initial is not None else prob.initial(omega=om0, params=P0)
        X0, _, _ = prob.newton(X0, om0, P0, tol)
        monitor = (lambda X, om, P: ihb_multipliers(prob, X, om, P, stability)) if stability else None

        def make_solution(X, om, P, rn, it, mu):
            return prob.solution(X, om, P, rn, it, mu)
    elif method == "shooting":
        from .nonlinear.integrate import consistent_state
        tol = 1e-9 if tol is None else tol
        if initial is None:  # start from the IHB orbit at the first parameter value
            from .dae.ihb import ihb
            initial = ihb(system, om0, harmonics, samples=samples, subharmonic=subharmonic, stability=None, params=P0)
        q, qd = initial(0.0)[0], initial.velocity(0.0)[0]
        q, qd = consistent_state(system, q, qd, 0.0, om0, P0)
        prob = ShootingProblem(system, q, subharmonic, samples=shooting_samples)
        X0, _, _, _ = prob.newton(prob.state(q, qd), om0, P0, tol)
        cache = {}
        orig = prob.residual_jacobian

        def residual_jacobian(X, om, P):
            R, J = orig(X, om, P)
            cache[(X.tobytes(), om, tuple(sorted(P.items())))] = J
            return R, J
        prob.residual_jacobian = residual_jacobian

        def monitor(X, om, P):
            J = cache.get((X.tobytes(), om, tuple(sorted(P.items()))))
            if J is None:
                J = orig(X, om, P)[1]
            cache.clear()
            return np.linalg.eigvals(J + np.eye(prob.size))

        def make_solution(X, om, P, rn, it, mu):
            return prob.solution(X, om, P, rn, it, mu, harmonics)
    else:
        raise InputError(f"method must be 'ihb' or 'shooting', got {method!r}")

    scales = _group_scales(prob, X0)
    Xs, ps, sols, mus, res, its, specials, status = pseudo_arclength(
        prob, X0, p0, p1, set_parameter=set_parameter, parameter_name=name, scales=scales, tangent=tangent, ds=ds,
        ds_min=ds_min, ds_max=ds_max, max_points=max_points, tol=tol, monitor=monitor, make_solution=make_solution)
    oms = np.array([set_parameter(p)[0] for p in ps])
    stable = np.array([s.stable for s in sols], dtype=object if any(s.stable is None for s in sols) else bool)
    options = dict(method=method, harmonics=harmonics, samples=getattr(prob, "p", None), subharmonic=subharmonic,
                   stability=stability, ds_max=ds_max, tol=tol, system=system)
    return Branch(oms, np.array(ps), name, np.array([s.amplitude() for s in sols]), stable,
                  np.array([s.max_multiplier for s in sols]), np.array(res), np.array(its), tuple(specials),
                  tuple(sols), status, prob, options, np.array(Xs))


def switch_period_doubling(branch: Branch, point: SpecialPoint, p_stop: float, *, amplitude: float = 1e-2,
                           **kwargs) -> Branch:
    """Follow the period-doubled (period 2T) branch born at a period-doubling ``point`` of
    an IHB ``branch``, toward parameter ``p_stop``.

    The T-periodic solution nearest the point is re-expressed with base frequency omega/2
    (harmonics 2H, only even ones non-zero); the critical Floquet mode (eigenvector of
    the multiplier near -1, integrated over 2T, mapped to q by the null-space basis) has
    only odd harmonics of omega/2 and is orthogonal to that branch, so it is the initial
    tangent of the new branch (the PD point is a pitchfork of the 2T problem).
    amplitude: relative size of the first step along the mode. kwargs go to continuation.
    """
    from .dae.fourier import real_coefficients
    from .dae.ihb import IHBProblem
    from .dae.solution import PeriodicSolution
    from .dae.stability import _interpolate, monodromy, propagate, reduce_linearization

    if point.type != "period-doubling":
        raise InputError(f"point is a {point.type!r}, not a period-doubling point")
    prob = branch.problem
    if not isinstance(prob, IHBProblem):
        raise InputError("branch switching needs an IHB branch")
    system = branch.options["system"]
    k = point.index if abs(branch.parameter[point.index] - point.parameter) <= abs(
        branch.parameter[point.index + 1] - point.parameter) else point.index + 1
    name = branch.parameter_name
    P0 = branch.solutions[k].parameters
    om = point.omega
    P = P0 if name is None else dict(P0, **{name: point.parameter})
    # the T-orbit exactly at the bifurcation point
    Xpd, rn, _ = prob.newton(branch.unknowns[k], om, P, branch.options["tol"])
    sol = prob.solution(Xpd, om, P, rn, 0, None)
    H = prob.H
    # T-periodic solution in the 2T basis: harmonic k of omega -> harmonic 2k of omega/2
    H2 = 2 * H
    cq = np.zeros((2 * H2 + 1, system.n), complex)
    cl = np.zeros((2 * H2 + 1, system.m), complex)
    cq[H2 + 2 * np.arange(-H, H + 1)] = sol.harmonics
    cl[H2 + 2 * np.arange(-H, H + 1)] = sol.lambda_harmonics
    prob2 = IHBProblem(system, H2, kwargs.pop("samples", None), 2 * prob.nu)
    start = PeriodicSolution(om, 2 * prob.nu, cq, cl, sol.residual, 0, None, "ihb", P, sol.coordinate_names,
                             sol.constraint_names, prob2.p)
    X2 = prob2.from_solution(start)
    # critical Floquet mode: eigenvector of mu ~ -1, propagated over 2T to the 2T sample times
    red = reduce_linearization(system, *prob.time_samples(Xpd, om), om, P, 2 * np.pi * prob.nu / om)
    mu, V = np.linalg.eig(monodromy(red))
    y = V[:, int(np.argmin(np.abs(mu + 1)))].real
    t2 = prob2.theta / (om / prob2.nu)
    zs = np.empty((prob2.p, red.r))
    for i in range(prob2.p):
        zs[i] = y[: red.r]
        if i + 1 < prob2.p:
            y = propagate(red, t2[i], t2[i + 1], 8) @ y
    basis = _interpolate(red.basis, 2 * np.pi * t2 / red.period)
    dq = np.einsum("pnr,pr->pn", basis, zs)
    dX = prob2.join(real_coefficients(dq, H2), np.zeros((prob2.L, system.m)))
    scale_q = np.sqrt(np.mean(X2[: system.n * prob2.L] ** 2)) or 1.0
    dX *= amplitude * scale_q * np.sqrt(system.n * prob2.L) / max(np.linalg.norm(dX), 1e-300)
    tangent = np.concatenate([dX, [0.0]])
    p_here = om if name is None else P[name]
    omega_arg = (p_here, p_stop) if name is None else om
    param_arg = None if name is None else (name, p_here, p_stop)
    opts = {kk: branch.options[kk] for kk in ("stability",) if kk in branch.options}
    opts.update(kwargs)
    return continuation(system, omega_arg, H2, "ihb", param_arg, initial=start, subharmonic=2 * prob.nu,
                        samples=prob2.p, tangent=tangent, **opts)

