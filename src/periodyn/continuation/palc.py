"""Pseudo-arc-length continuation of ``R(X, p) = 0``: predictor, corrector, step control.

The driver only sees ``equations(X, p) -> (R (N,), J)`` (J sparse or dense) and
``residual(X, p)``; dR/dp is a central difference in the one scalar p (never used in the
Newton Jacobian of the discretization, only in the bordered rows).

Scaling: unknowns are compared in the weighted norm
``|dX|^2 = sum_i (dX_i / s_i)^2 / N + (dp / s_p)^2`` with per-unknown scales s (the RMS of
each unknown group, e.g. displacement and multiplier coefficients, at the first point, and
raised to the largest RMS met on the branch since: a branch starting at a tiny amplitude
must not keep steps of that size through its resonance) and s_p = |p_0|.
Steps: tangent predictor, Newton corrector (``periodyn.nonlinear.newton``) on the bordered
system (R = 0 plus the hyperplane through the predictor normal to the tangent); ds grows
x1.5 after an easy step (<= 3 iterations), shrinks x0.7 after a hard one (>= 6), halves
after a failed step down to ds_min, and a step that turns the tangent by more than ~25
degrees (cos < 0.9) is retried shorter.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterator

import numpy as np
import scipy.linalg as sla

from ..errors import ConvergenceError, InputError
from ..nonlinear.newton import lu_factor, newton

__all__ = ["Arc", "ArcPoint", "trace"]

_H_REL = 1e-6  # relative step of the central difference dR/dp


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
    reusing the last one.
    """

    def __init__(self, equations: Callable, residual: Callable, groups, X0: np.ndarray, p0: float, tol: float,
                 max_iter: int, dR_dp: Callable | None = None, exact_tangents: bool = False):
        self.equations, self.residual, self.tol, self.max_iter = equations, residual, tol, max_iter
        self._dR_dp, self.exact_tangents = dR_dp, exact_tangents
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
        h = _H_REL * max(abs(p), 1e-3)
        return (self.residual(X, p + h) - self.residual(X, p - h)) / (2 * h)

    def norm(self, d: np.ndarray) -> float:
        return float(np.sqrt(np.sum(self.w * d[:self.N] ** 2) + self.wp * d[self.N] ** 2))

    def dot(self, a: np.ndarray, b: np.ndarray) -> float:
        return float(np.sum(self.w * a[:self.N] * b[:self.N]) + self.wp * a[self.N] * b[self.N])

    def bordered_solve(self, solve, Rp, t, r_x, r_p) -> np.ndarray:
        """[[J, Rp], [w t_X, wp t_p]] [x; y] = [r_x; r_p] by block elimination (two solves
        with the factorization of J; keeps its sparse structure)."""
        a, b = solve(r_x), solve(Rp)
        row = self.w * t[:self.N]
        y = (r_p - row @ a) / (self.wp * t[self.N] - row @ b)
        return np.concatenate([a - b * y, [y]])

    def tangent(self, X, p, J, t_old, solve=None, Rp=None) -> np.ndarray:
        """Unit tangent at (X, p), oriented along t_old (solve: a factorization of J to reuse;
        Rp: dR/dp at (X, p) if known)."""
        Rp = self.dR_dp(X, p) if Rp is None else Rp
        t = self.bordered_solve(solve or lu_factor(J), Rp, t_old, np.zeros(self.N), 1.0)
        t /= self.norm(t)
        return -t if self.dot(t, t_old) < 0 else t

    def correct(self, Xp, pp, t, exact_tangent: bool = False) -> ArcPoint:
        """Newton on R = 0 and the hyperplane through (Xp, pp) normal to t; raises
        ConvergenceError. The returned tangent reuses the last factorization of J (one LU
        less per point; the predictor needs no more) unless ``exact_tangent``."""
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


def trace(arc: Arc, start: ArcPoint, p_stop: float, *, ds: float, ds_min: float, ds_max: float,
          max_points: int) -> Iterator[ArcPoint | str]:
    """Accepted points after ``start`` until p passes p_stop; the last item yielded is the
    status string (why the branch ended)."""
    direction = np.sign(p_stop - start.p) or 1.0
    pt, count = start, 1
    while count < max_points:
        if (pt.p - p_stop) * direction >= 0 and count > 1:
            yield "parameter range covered"
            return
        if arc.follow(pt.X):  # the branch grew: steps in the new scale, tangent of unit length in it
            pt = ArcPoint(pt.X, pt.p, pt.t / arc.norm(pt.t), pt.residual, pt.iterations)
        new = None
        while ds >= ds_min:
            try:
                new = arc.correct(pt.X + ds * pt.t[:arc.N], pt.p + ds * pt.t[arc.N], pt.t)
            except (ConvergenceError, np.linalg.LinAlgError, sla.LinAlgWarning, FloatingPointError, ValueError,
                    RuntimeError):
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
        pt, count = new, count + 1
        if new.iterations <= 3:
            ds = min(ds * 1.5, ds_max)
        elif new.iterations >= 6:
            ds *= 0.7
    yield (f"max_points reached: {max_points} points ended at parameter {pt.p:.6g} before the stop {p_stop:.6g}; "
           f"raise max_points, or ds_max (now {ds_max:g}) for longer steps")


def first_point(arc: Arc, X0, p0: float, p_stop: float, tangent=None) -> ArcPoint:
    """The start point (must solve R = 0) with its tangent toward p_stop (or ``tangent``)."""
    R, J = arc.equations(np.asarray(X0, float), p0)
    r0 = float(np.max(np.abs(R)))
    if r0 > arc.tol:
        raise InputError(f"the start point is not a solution (residual {r0:.3g} > {arc.tol:.1g}); converge it first")
    if tangent is None:
        t_old = np.zeros(arc.N + 1)
        t_old[arc.N] = np.sign(p_stop - p0) or 1.0
        t = arc.tangent(np.asarray(X0, float), p0, J, t_old)
        if t[arc.N] * t_old[arc.N] < 0:
            t = -t
    else:
        t = np.asarray(tangent, float) / arc.norm(np.asarray(tangent, float))
    return ArcPoint(np.array(X0, float), float(p0), t, r0, 0)
