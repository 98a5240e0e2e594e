"""Pseudo-arc-length continuation of ``R(X, p) = 0``: predictor, corrector, step control.

The driver only sees ``equations(X, p) -> (R (N,), J)`` (J sparse or dense) and
``residual(X, p)``; dR/dp is a central difference in the one scalar p (never used in the
Newton Jacobian of the discretization, only in the bordered rows).

Scaling: unknowns are compared in the weighted norm
``|dX|^2 = sum_i (dX_i / s_i)^2 / N + (dp / s_p)^2`` with per-unknown scales s (the RMS of
each unknown group, e.g. displacement and multiplier coefficients, at the first point, and
raised to the largest RMS met on the branch since: a branch starting at a tiny amplitude
must not keep steps of that size through its resonance) and s_p = |p_0|.
Steps: tangent predictor, Newton corrector (``periodyn.numerics.newton_iteration``) on the bordered
system (R = 0 plus the hyperplane through the predictor normal to the tangent); ds grows
x1.5 after an easy step (<= 3 iterations), shrinks x0.7 after a hard one (>= 6), and is
scaled besides so that the tangent turns by about ``_TURN`` radians per step (x0.5 to x1.5:
points gather where the branch bends, at folds, and not on straight stretches); it halves
after a failed step down to ds_min, and a step that turns the tangent by more than ~25
degrees (cos < 0.9) is retried shorter.

Factorization reuse (``Arc(..., reuse=True)``, for discretizations whose sparse Jacobian
costs many residuals to factorize, as the IHB one): the corrector is a chord (Shamanskii)
iteration. It starts with the factorization kept at the point the predictor left, does
updates with residuals only while each shrinks the residual max-norm by at least
``_CHORD_RATE``, and factorizes J at the current iterate when one does not (at most
max_iter factorizations, ``_CHORD_UPDATES`` x max_iter updates). The tangent at the
converged point is exact: its bordered system with J there is solved by GMRES
(``periodyn.numerics.krylov``) to ``_KRYLOV_TOL``, preconditioned with the corrector's
last factorization, and J is factorized there only when GMRES needs more than
``_KRYLOV_STEPS`` steps. The factorization used is kept for the next step from that
point. Converged points solve R = 0 to tol as before; the step control counts chord
updates (``_CHORD_EASY``: at most this many grow ds, at least this many shrink it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Iterator

import numpy as np
import scipy.linalg as sla

from ..errors import ConvergenceError, InputError
from ..numerics.krylov import gmres
from ..numerics.newton_iteration import lu_factor, newton

__all__ = ["Arc", "ArcPoint", "land", "trace", "difference_step"]

_H_REL = 1e-6  # relative step of the central difference dR/dp
_CHORD_RATE = 0.5  # reuse mode: a chord update must shrink the residual this much, else J is factorized
_CHORD_UPDATES = 3  # reuse mode: updates allowed per factorization allowed
_CHORD_EASY = (6, 12)  # reuse mode: step control thresholds in chord updates (Newton: 3, 6)
_KRYLOV_TOL = 1e-10  # reuse mode: relative residual of the tangent's GMRES solve
_KRYLOV_STEPS = 12  # reuse mode: GMRES steps before J is factorized for the tangent
_KEEP = 4  # preconditioners kept at the latest accepted points (reuse mode)
_TURN = 0.15  # radians the tangent turns per step under the step control (trace)


@dataclass(frozen=True, eq=False)
class ArcPoint:
    """An accepted point: X (N,), p, unit tangent t (N+1,), residual max-norm, iterations."""

    X: np.ndarray
    p: float
    t: np.ndarray
    residual: float
    iterations: int


class Arc:
    """Bordered system of one continuation problem.

    equations(X, p) -> (R, J); residual(X, p) -> R; groups: index arrays of the unknown
    groups sharing a scale (None: one group); X0 (N,) the first point, p0 sets the
    parameter scale; tol: residual max-norm; max_iter: corrector Newton updates;
    dR_dp(X, p): the discretization's own parameter derivative (default: central
    difference of residual); exact_tangents: factorize the J at each accepted point for
    its tangent (for correctors whose updates use approximate Jacobians) instead of
    reusing the last one; reuse: chord corrector and exact tangents by GMRES, both with
    kept factorizations (module docstring).
    """

    def __init__(self, equations: Callable, residual: Callable, groups, X0: np.ndarray, p0: float, tol: float,
                 max_iter: int, dR_dp: Callable | None = None, exact_tangents: bool = False, reuse: bool = False):
        self.equations, self.residual, self.tol, self.max_iter = equations, residual, tol, max_iter
        self._dR_dp, self.exact_tangents, self.reuse = dR_dp, exact_tangents, reuse
        self._kept = []  # (X, preconditioner) at the latest accepted points, newest last (reuse mode)
        self.N = len(X0)
        self.groups = [g for g in (groups or [np.arange(self.N)]) if len(g)]
        ref = max(np.sqrt(np.mean(np.asarray(X0) ** 2)), 1e-12)
        self.floor = max(1e-6 * ref, 1e-12)
        self.scales = np.empty(len(self.groups))
        self.follow(X0, first=True)
        self.wp = 1.0 / max(abs(p0), 1e-6) ** 2

    def follow(self, X, first: bool = False) -> bool:
        """Raise the group scales to the RMS of X where it is larger; True when any changed."""
        rms = np.array([max(np.sqrt(np.mean(X[g] ** 2)), self.floor) for g in self.groups])
        grow = first or bool(np.any(rms > self.scales))
        if grow:
            self.scales = rms if first else np.maximum(self.scales, rms)
            self.w = np.empty(self.N)
            for g, sc in zip(self.groups, self.scales):
                self.w[g] = 1.0 / (sc ** 2 * self.N)
        return grow

    def dR_dp(self, X, p) -> np.ndarray:
        if self._dR_dp is not None:
            return self._dR_dp(X, p)
        h = difference_step(p)
        return (self.residual(X, p + h) - self.residual(X, p - h)) / (2 * h)

    def norm(self, d: np.ndarray) -> float:
        return math.sqrt(self.dot(d, d))

    def dot(self, a: np.ndarray, b: np.ndarray) -> float:
        N = self.N
        return float((self.w * a[:N]) @ b[:N] + self.wp * a[N] * b[N])

    def bordered_solve(self, solve, Rp, t, r_x, r_p, b=None) -> np.ndarray:
        """[[J, Rp], [w t_X, wp t_p]] [x; y] = [r_x; r_p] by block elimination (two solves
        with the factorization of J, one when b = solve(Rp) is given; keeps its sparse
        structure)."""
        a, b = solve(r_x), solve(Rp) if b is None else b
        row = self.w * t[:self.N]
        y = (r_p - row @ a) / (self.wp * t[self.N] - row @ b)
        return np.concatenate([a - b * y, [y]])

    def tangent(self, X, p, J, t_old, solve=None, Rp=None) -> np.ndarray:
        """Unit tangent at (X, p), oriented along t_old (solve: a factorization of J to reuse;
        Rp: dR/dp at (X, p) if known). In reuse mode the factorization is kept as the
        preconditioner of the next step from X."""
        Rp = self.dR_dp(X, p) if Rp is None else Rp
        if self.reuse and solve is None:
            pre = self._factor(J, Rp)
            self._kept = self._kept[1 - _KEEP:] + [(X, pre)]
            return self._oriented(self.bordered_solve(*pre[:2], t_old, np.zeros(self.N), 1.0, pre[2]), t_old)
        t = self.bordered_solve(solve or lu_factor(J), Rp, t_old, np.zeros(self.N), 1.0)
        return self._oriented(t, t_old)

    def exact_tangent(self, X, p, t_old, start: ArcPoint | None = None) -> np.ndarray:
        """Unit tangent at the solution (X, p) from J there, oriented along t_old, as the
        corrector's exact tangent at a converged point (in reuse mode by GMRES preconditioned
        with the factorization kept at ``start``, kept in turn for X)."""
        J, Rp = self.equations(X, p)[1], self.dR_dp(X, p)
        if not self.reuse:
            return self._oriented(self.bordered_solve(lu_factor(J), Rp, t_old, np.zeros(self.N), 1.0), t_old)
        pre = next((q for Y, q in self._kept if start is not None and Y is start.X), None)
        d, pre = self._krylov_solve(J, Rp, t_old, np.zeros(self.N), 1.0, pre)
        self._kept = self._kept[1 - _KEEP:] + [(X, pre)]
        return self._oriented(d, t_old)

    def _oriented(self, t, t_old) -> np.ndarray:
        t = t / self.norm(t)
        return -t if self.dot(t, t_old) < 0 else t

    def _factor(self, J, Rp) -> tuple:
        """Preconditioner (solve, Rp, solve(Rp)) of the bordered systems with J."""
        solve = lu_factor(J)
        return solve, Rp, solve(Rp)

    def _krylov_solve(self, J, Rp, t, r_x, r_p, pre):
        """Bordered solve with the exact J and Rp by GMRES preconditioned with ``pre`` (or by
        a fresh factorization when there is none or GMRES is slow); returns (x, pre used)."""
        N = self.N
        if pre is not None:
            row = np.concatenate([self.w * t[:N], [self.wp * t[N]]])
            x, rel, _ = gmres(lambda v: np.concatenate([J @ v[:N] + Rp * v[N], [row @ v]]),
                              np.concatenate([r_x, [r_p]]),
                              lambda v: self.bordered_solve(*pre[:2], t, v[:N], v[N], pre[2]), rtol=_KRYLOV_TOL,
                              max_steps=_KRYLOV_STEPS)
            if rel <= _KRYLOV_TOL:
                return x, pre
        pre = self._factor(J, Rp)
        return self.bordered_solve(*pre[:2], t, r_x, r_p, pre[2]), pre

    def correct(self, Xp, pp, t, exact_tangent: bool = False, start: ArcPoint | None = None) -> ArcPoint:
        """Newton on R = 0 and the hyperplane through (Xp, pp) normal to t; raises
        ConvergenceError. The returned tangent reuses the last factorization of J (one LU
        less per point; the predictor needs no more) unless ``exact_tangent``. In reuse mode
        its solves are preconditioned with the factorization kept at ``start``, the point
        the predictor left, when there is one (module docstring)."""
        if self.reuse:
            return self._reuse_correct(Xp, pp, t, start)
        N, z0 = self.N, np.concatenate([Xp, [pp]])

        def equations(z):
            R, J = self.equations(z[:N], z[N])
            return np.concatenate([R, [self.dot(t, z - z0)]]), (J, self.dR_dp(z[:N], z[N]))

        last = [None]  # the latest factorization of J, reused for the tangent (one LU less per point)

        def factor(JR):
            last[0] = lu_factor(JR[0])
            return lambda r: self.bordered_solve(last[0], JR[1], t, r[:N], r[N])

        res = newton(equations, z0, tol=self.tol, max_iter=self.max_iter, factor=factor, label="continuation corrector",
                     hint="reduce ds")
        X, p = res.x[:N], float(res.x[N])
        J, Rp = res.jacobian
        reuse = None if exact_tangent or self.exact_tangents else last[0]
        return ArcPoint(X, p, self.tangent(X, p, J, t, reuse, Rp), res.residual,
                        res.iterations)

    def _reuse_correct(self, Xp, pp, t, start) -> ArcPoint:
        """Chord corrector with an exact tangent (module docstring); iterations counts the
        updates; raises ConvergenceError."""
        N, z0 = self.N, np.concatenate([Xp, [pp]])
        pre = next((q for X, q in self._kept if start is not None and X is start.X), None)
        z, rn_old, updates, factorizations = z0, np.inf, 0, 0
        while True:
            R = self.residual(z[:N], z[N])
            hyper = self.dot(t, z - z0)
            rn = max(float(np.max(np.abs(R), initial=0.0)), abs(hyper))
            if rn <= self.tol or not np.isfinite(rn) or updates == _CHORD_UPDATES * self.max_iter:
                break
            if pre is None or rn > _CHORD_RATE * rn_old:  # poor contraction: J at this iterate
                if factorizations == self.max_iter:
                    break
                R, J = self.equations(z[:N], z[N])
                pre = self._factor(J, self.dR_dp(z[:N], z[N]))
                factorizations += 1
            dz = self.bordered_solve(*pre[:2], t, -R, -hyper, pre[2])
            if not np.all(np.isfinite(dz)):
                break
            z, rn_old, updates = z + dz, rn, updates + 1
        if not rn <= self.tol:
            raise ConvergenceError(f"continuation corrector did not converge: residual {rn:.3g} > tol {self.tol:.1g} "
                                   f"after {updates} chord updates with {factorizations} factorizations; reduce ds",
                                   rn, updates)
        X, p = z[:N], float(z[N])
        d, pre = self._krylov_solve(self.equations(X, p)[1], self.dR_dp(X, p), t, np.zeros(N), 1.0, pre)
        self._kept = self._kept[1 - _KEEP:] + [(X, pre)]
        return ArcPoint(X, p, self._oriented(d, t), rn, updates)


def trace(arc: Arc, start: ArcPoint, p_stop: float, *, ds: float, ds_min: float, ds_max: float,
          max_points: int, bounds: tuple[float, float] | None = None,
          positive: bool = False) -> Iterator[ArcPoint | str]:
    """Accepted points after ``start`` until the branch reaches p_stop; the last item yielded
    is the status string (why the branch ended).

    bounds: (lo, hi) the parameter never leaves (default: from start.p to p_stop, either
    side open); positive: p > 0 besides (a driving speed). A predictor beyond a bound is
    shortened to land on it, and a corrected point beyond it is re-solved at the bound
    itself (fixed p, :func:`land`): a branch ends exactly on p_stop, or on the other bound
    when it turns back out of the range. A predictor to p <= 0 is cut back to half the way
    to 0, and a corrected point at p <= 0 is a failed step."""
    direction = np.sign(p_stop - start.p) or 1.0
    lo, hi = bounds if bounds is not None else sorted((p_stop, -direction * np.inf))
    pt, count = start, 1
    while count < max_points:
        if arc.follow(pt.X):  # the branch grew: steps in the new scale, tangent of unit length in it
            pt = ArcPoint(pt.X, pt.p, pt.t / arc.norm(pt.t), pt.residual, pt.iterations)
        new = None
        while ds >= ds_min:
            step = _inside(pt, ds, arc.N, lo, hi, positive)
            try:
                new = arc.correct(pt.X + step * pt.t[:arc.N], pt.p + step * pt.t[arc.N], pt.t, start=pt)
                if not lo <= new.p <= hi:
                    new = land(arc, pt, new, hi if new.p > hi else lo)
            except (ConvergenceError, np.linalg.LinAlgError, sla.LinAlgWarning, FloatingPointError, ValueError,
                    RuntimeError):
                new = None
            if new is not None and positive and not new.p > 0:
                new = None
            if new is not None and not (arc.dot(new.t, pt.t) < 0.9 and ds > ds_min * 2):
                break
            new = None
            ds *= 0.5
        if new is None:
            yield (f"step size below ds_min={ds_min:g} at parameter {pt.p:.6g} (stop {p_stop:.6g}): the corrector "
                   f"failed; lower ds_min, raise max_iter (now {arc.max_iter}), or, at a branch point, follow the "
                   "other branch with switch_branch")
            return
        yield new
        prev, pt, count = pt, new, count + 1
        if pt.p == p_stop:
            yield "parameter range covered"
            return
        if pt.p in (lo, hi):
            yield (f"the branch turned back and left the range at parameter {pt.p:.6g} (its start side; stop "
                   f"{p_stop:.6g}): widen the range to follow it")
            return
        easy, hard = _CHORD_EASY if arc.reuse else (3, 6)
        grow = 1.5 if new.iterations <= easy else 0.7 if new.iterations >= hard else 1.0
        ds = min(ds * min(grow, _turn_factor(arc, prev, pt) if count > 2 else grow), ds_max)
    yield (f"max_points reached: {max_points} points ended at parameter {pt.p:.6g} before the stop {p_stop:.6g}; "
           f"raise max_points, or ds_max (now {ds_max:g}) for longer steps")


def difference_step(p: float) -> float:
    """Step h of the central difference dR/dp at parameter p."""
    return _H_REL * max(abs(p), 1e-3)


def _turn_factor(arc: Arc, a: ArcPoint, b: ArcPoint) -> float:
    """Step factor from the turn of the tangent between accepted points a and b: the angle
    (scaled norm) brought to ``_TURN`` radians per step, the factor within [0.5, 1.5]; a
    fold, where the branch turns fastest, gets short steps, a straight stretch long ones. Not
    used on the first step (the start's tangent may be given, as on a switched branch)."""
    cos = arc.dot(a.t, b.t) / (arc.norm(a.t) * arc.norm(b.t))
    angle = math.acos(min(max(cos, -1.0), 1.0))
    return min(max(_TURN / max(angle, 1e-12), 0.5), 1.5)


def _inside(pt: ArcPoint, ds: float, N: int, lo: float, hi: float, positive: bool) -> float:
    """The step ds, shortened so that the predictor's parameter stays within [lo, hi] (landing
    on the bound it would cross) and, when positive, above half the way to 0."""
    tp = pt.t[N]
    p = pt.p + ds * tp
    if p > hi and tp > 0:
        ds = (hi - pt.p) / tp
    elif p < lo and tp < 0:
        ds = (lo - pt.p) / tp
    if positive and pt.p + ds * tp <= 0 and tp < 0:
        ds = 0.5 * pt.p / -tp
    return ds


def land(arc: Arc, a: ArcPoint, b: ArcPoint, p: float) -> ArcPoint:
    """The branch point at parameter exactly p between accepted a and corrected b (p between
    theirs): Newton at fixed p from the linear interpolation, its tangent oriented along b's;
    raises ConvergenceError."""
    f = (p - a.p) / (b.p - a.p)
    t = np.zeros(arc.N + 1)
    t[arc.N] = 1.0
    pt = arc.correct(a.X + f * (b.X - a.X), p, t, start=a)
    tt = pt.t if arc.dot(pt.t, b.t) >= 0 else -pt.t
    return ArcPoint(pt.X, p, tt, pt.residual, pt.iterations)


def first_point(arc: Arc, X0, p0: float, p_stop: float, tangent=None) -> ArcPoint:
    """The start point (must solve R = 0) with its tangent toward p_stop (or ``tangent``)."""
    X0 = np.array(X0, float)
    R, J = arc.equations(X0, p0)
    r0 = float(np.max(np.abs(R)))
    if r0 > arc.tol:
        raise InputError(f"the start point is not a solution (residual {r0:.3g} > {arc.tol:.1g}); converge it first")
    if tangent is None:
        t_old = np.zeros(arc.N + 1)
        t_old[arc.N] = np.sign(p_stop - p0) or 1.0
        t = arc.tangent(X0, p0, J, t_old)
        if t[arc.N] * t_old[arc.N] < 0:
            t = -t
    else:
        t = np.asarray(tangent, float) / arc.norm(np.asarray(tangent, float))
    return ArcPoint(X0, float(p0), t, r0, 0)
