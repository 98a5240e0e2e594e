"""Special points between two branch points: one classifier, one root refinement.

Classification (:func:`classify`): a fold where the parameter component of the tangent,
dp/ds, changes sign; a multiplier crossing of the unit circle typed by the one classifier
of :mod:`periodyn.stability.crossings` (period doubling through -1, Neimark-Sacker for a
complex pair); a crossing of +1 is a branch point (symmetry-breaking pitchfork or
transcritical) while dp/ds keeps its sign (with a sign change of dp/ds it is the fold).
Refinement (:func:`illinois`): the Illinois (modified regula falsi) method on a scalar
indicator g(s) over a bracket s in [0, 1]; folds use g = dp/ds along the arc (each trial
point solved by the corrector, the bracket's far end the accepted point itself with its
exact tangent; the first trial where the cubic matching p and dp/ds at both ends turns,
then inverse quadratic steps through the three latest values where they land inside the
bracket, as in Brent's method), multiplier crossings fixed-parameter Newton solves with
g = :func:`crossing_test` (period doubling, Neimark-Sacker) or :func:`branch_test` (branch
point). One bracket reports each type once: two multipliers of one kind leaving in one step
have one refined location (the test function's root), so a second entry would repeat it.

Registry (:data:`SPECIAL_POINTS`): the built-in special points by name with their test
functions. Users add their own with :class:`Event` (``continuation(..., events=[Event(name,
test)])``): ``test`` sees an :class:`EventPoint` at every branch point; where it changes sign
between two consecutive points, the same refinement (fixed-parameter Newton solves, Illinois
on the test) locates its root, recorded among the branch's special points with type ``name``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any, Callable

import numpy as np
import scipy.linalg as sla

from ..errors import ConvergenceError, InputError
from ..numerics.newton_iteration import lu_factor, newton
from ..stability.crossings import KINDS, classify_crossing, of_kind
from .palc import ArcPoint

__all__ = ["Event", "EventPoint", "KINDS", "SPECIAL_POINTS", "branch_test", "check_events", "classify",
           "crossing_test", "fold_test", "illinois", "null_vector", "of_kind", "refine_crossing", "refine_fold",
           "same_point"]


def _nearest(sel) -> complex:
    """The entry of sel nearest the unit circle in |log|mu|| (nan when sel is empty)."""
    if not len(sel):
        return complex("nan")
    return complex(sel[int(np.argmin(np.abs(np.log(np.maximum(np.abs(sel), 1e-300)))))])


def nearest_of_kind(mu, kind: str) -> complex:
    """The multiplier of one kind nearest the unit circle (nan when there is none)."""
    return _nearest(of_kind(mu, kind))


def crossing_test(mu, typ: str) -> float:
    """Test function of period doubling and Neimark-Sacker points: |mu| - 1 of the
    multiplier of the crossing kind nearest the unit circle (other multipliers, already
    outside or of another kind, do not move its root); without a multiplier of that kind
    (e.g. the complex pair that turns real on the way to -1) the nearest one that is not
    real positive."""
    c = nearest_of_kind(mu, KINDS[typ])
    if not np.isfinite(c):
        mu = np.asarray(mu, complex)
        c = _nearest(np.setdiff1d(mu, of_kind(mu, "real > 0")))
    return float(abs(c) - 1.0)


def branch_test(mu) -> float:
    """Branch-point test function of multipliers mu: sign(Re prod(mu_i - 1)) min|mu_i - 1|.

    prod(mu_i - 1) = det(M - I) changes sign exactly when a real multiplier crosses +1
    (a complex pair contributes |mu - 1|^2 > 0); the factor min|mu_i - 1| makes the value
    the distance of the critical multiplier from +1, independent of the other multipliers.
    """
    d = np.asarray(mu) - 1.0
    return float(np.sign(np.prod(d / np.maximum(np.abs(d), 1e-300)).real) * np.min(np.abs(d)))


def fold_test(tangent) -> float:
    """Fold test function: dp/ds, the parameter (last) component of the branch tangent."""
    return float(tangent[-1])


#: the built-in special points: name -> test function (of the tangent for the fold, of the
#: Floquet multipliers otherwise); ``classify`` finds their brackets, the driver refines them
SPECIAL_POINTS: dict[str, Callable] = {
    "fold": fold_test,
    "branch-point": branch_test,
    "period-doubling": partial(crossing_test, typ="period-doubling"),
    "neimark-sacker": partial(crossing_test, typ="neimark-sacker"),
}


@dataclass(frozen=True, eq=False)
class EventPoint:
    """What an event test sees: one orbit of the branch (a branch point, or a trial point of
    the refinement).

    omega: driving frequency, rad/s; parameter: the continued parameter's value (omega for a
    frequency response); amplitude (n,): half peak-to-peak per coordinate; harmonics
    (2H+1, n) complex, l = -H..H; multipliers: Floquet multipliers (None when stability is
    not computed); solution: the PeriodicSolution (``solution(t)`` -> q (len(t), n),
    ``solution.velocity(t)``, ``solution.mean``).
    """

    omega: float
    parameter: float
    amplitude: np.ndarray
    harmonics: np.ndarray
    multipliers: np.ndarray | None
    solution: Any


@dataclass(frozen=True, eq=False)
class Event:
    """A user continuation event: a special point of type ``name`` wherever ``test`` changes
    sign between two consecutive branch points.

    test(point: EventPoint) -> float, finite at every branch point; tol: |test| at which the
    refinement stops (the test's units). Example: ``Event("amplitude 0.5", lambda pt:
    pt.amplitude[0] - 0.5)``.
    """

    name: str
    test: Callable[[EventPoint], float]
    tol: float = 1e-9

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError(f"Event name must be a non-empty string (the special point's type), got {self.name!r}")
        if self.name in SPECIAL_POINTS:
            raise InputError(f"Event name {self.name!r} is a built-in special point (located without an event); "
                             "choose another name")
        if not callable(self.test):
            raise InputError(f"Event {self.name!r}: test must be a callable of the branch point returning a float, "
                             f"got {type(self.test).__name__}")
        if not (isinstance(self.tol, (int, float)) and np.isfinite(self.tol) and self.tol > 0):
            raise InputError(f"Event {self.name!r}: tol must be a finite number > 0, got {self.tol!r}")

    def value(self, solution, parameter: float) -> float:
        """The test at the orbit ``solution`` (a PeriodicSolution) at parameter value ``parameter``;
        InputError when it is not a finite float."""
        point = EventPoint(float(solution.omega), float(parameter), solution.amplitude(), solution.harmonics,
                           solution.multipliers, solution)
        raw = self.test(point)
        try:
            v = float(raw)
        except (TypeError, ValueError):
            raise InputError(f"Event {self.name!r}: test must return a float, got {type(raw).__name__}") from None
        if not np.isfinite(v):
            raise InputError(f"Event {self.name!r}: test returned {v} at omega = {point.omega:.6g} rad/s; it must be "
                             "finite at every branch point")
        return v


def check_events(events) -> tuple:
    """``events`` as a tuple of :class:`Event` with distinct names, else InputError."""
    if isinstance(events, Event):
        events = (events,)
    try:
        events = tuple(events)
    except TypeError:
        raise InputError(f"events must be a list of periodyn.Event(name, test), got {type(events).__name__}") from None
    for ev in events:
        if not isinstance(ev, Event):
            raise InputError(f"events must be periodyn.Event(name, test) objects, got {type(ev).__name__}")
    names = [ev.name for ev in events]
    if len(set(names)) != len(names):
        raise InputError(f"event names must be distinct, got {names}")
    return events


def classify(tp_a: float, tp_b: float, mu_a, mu_b) -> list[tuple[str, complex, float]]:
    """Events between points a and b: (type, critical multiplier, linear estimate of the
    bracket fraction s in [0, 1]). tp: dp/ds at each point; mu: multipliers or None."""
    out = []
    if np.sign(tp_a) != np.sign(tp_b) and tp_a != 0:
        out.append(("fold", complex("nan"), tp_a / (tp_a - tp_b)))
    if mu_a is None or mu_b is None:
        return out
    na, nb = int(np.sum(np.abs(mu_a) > 1)), int(np.sum(np.abs(mu_b) > 1))
    if na == nb:
        return out
    grow = nb > na
    crit_side, other = (mu_b, mu_a) if grow else (mu_a, mu_b)
    for c in crit_side[np.abs(crit_side) > 1]:
        c2 = other[int(np.argmin(np.abs(other - c)))]  # the multiplier on the other side that continues c
        if abs(c2) > 1:
            continue
        typ = classify_crossing(c, c2)  # through +1: the fold's, or with dp/ds of one sign a branch point
        if typ == "fold" and out and out[0][0] == "fold":
            continue  # the +1 crossing of the fold, reported from dp/ds
        typ = "branch-point" if typ == "fold" else typ
        if any(o[0] == typ for o in out):
            continue  # one refined location per type and bracket
        if typ == "branch-point":
            fa, fb = branch_test(mu_a), branch_test(mu_b)
        else:
            fa, fb = (abs(c2) - 1, abs(c) - 1) if grow else (abs(c) - 1, abs(c2) - 1)
        out.append((typ, complex(c), fa / (fa - fb) if fa != fb else 0.5))
        if typ == "neimark-sacker":
            break  # one entry per complex pair
    return out


def illinois(g: Callable, a: tuple, b: tuple, *, ftol: float, stol: float, max_iter: int = 40,
             quadratic: bool = False, first: float | None = None):
    """Root of a scalar indicator bracketed by a = (s_a, g_a, data_a), b = (s_b, g_b, data_b).

    g(s, a, b) -> (g(s), data) or None when the trial point cannot be solved (then None is
    returned); the brackets are passed so a trial can start from their data. quadratic:
    each trial is the inverse quadratic interpolation of the three latest values (the
    bracket ends, then the trials) when they are distinct and it lies strictly inside the
    bracket, else the Illinois step (for a smooth g whose trials solve well anywhere in the
    bracket; a crossing's fixed-parameter Newton near a branch point does not). first: the
    first trial when strictly inside the bracket (a model's root), else the Illinois step.
    Stops when |g| < ftol or the bracket is shorter than stol; returns (s, data) of the last
    trial.
    """
    side = 0
    s, data = None, None
    seen = [a[:2], b[:2]]  # (s, g) of the bracket ends and the trials, oldest first
    for _ in range(max_iter):
        (sa, fa, da), (sb, fb, db) = a, b
        s = sa + fa * (sb - sa) / (fa - fb) if fa != fb else 0.5 * (sa + sb)
        q = first if len(seen) == 2 else _inverse_quadratic(*seen[-3:]) if quadratic else None
        if q is not None and min(sa, sb) < q < max(sa, sb):
            s = q
        res = g(s, a, b)
        if res is None:
            return None
        f, data = res
        seen.append((s, f))
        if abs(f) < ftol or abs(sb - sa) < stol:
            break
        if np.sign(f) == np.sign(fa):
            a = (s, f, data)
            if side == -1:
                b = (sb, 0.5 * fb, db)
            side = -1
        else:
            b = (s, f, data)
            if side == 1:
                a = (sa, 0.5 * fa, da)
            side = 1
    return s, data


def _inverse_quadratic(p0, p1, p2) -> float:
    """Root s of the quadratic s(g) through three points (s, g); NaN unless their g are distinct."""
    (s0, f0), (s1, f1), (s2, f2) = p0, p1, p2
    if f0 == f1 or f0 == f2 or f1 == f2:
        return float("nan")
    return (s0 * f1 * f2 / ((f0 - f1) * (f0 - f2)) + s1 * f0 * f2 / ((f1 - f0) * (f1 - f2))
            + s2 * f0 * f1 / ((f2 - f0) * (f2 - f1)))


def same_point(p1: float, g1: float, p2: float, g2: float, p_shared: float, g_shared: float, ftol: float) -> bool:
    """Whether roots p1, p2 of one test function, refined in two adjacent brackets (test
    values g1, g2 there), are one point.

    p_shared, g_shared: the branch point between the brackets and its test value; ftol: the
    |test| at which a refinement stops. Each root is located to ftol / slope, the slope
    taken by the secant from it to the shared point, plus 1e-12 relative (the refinement's
    shortest bracket); the roots are one when they lie within the sum of both tolerances.
    That holds when the test function at the shared point is itself within about ftol of
    zero: the two sign changes are one touch of zero, seen from either side.
    """
    def tolerance(p, g):
        slope = abs(g_shared - g) / max(abs(p_shared - p), 1e-300)
        return (ftol / slope if slope > 0 else np.inf) + 1e-12 * max(1.0, abs(p))

    return abs(p1 - p2) <= tolerance(p1, g1) + tolerance(p2, g2)


def null_vector(J, sweeps: int = 4) -> np.ndarray:
    """Unit null vector of the (nearly) singular Jacobian J at a fold or branch point, by
    inverse iteration with one factorization of J (the critical direction in the unknowns)."""
    solve = lu_factor(J)
    v = np.ones(J.shape[0]) / np.sqrt(J.shape[0])
    for _ in range(sweeps):
        v = solve(v)
        v /= np.linalg.norm(v)
    return v * np.sign(v[int(np.argmax(np.abs(v)))])


def refine_fold(arc, a, b, ftol: float):
    """Zero of dp/ds on the arc from a (trial points on the tangent line of a, each solved
    by the corrector on the hyperplane normal to it; the bracket's far end is b, which lies
    on such a hyperplane, with its exact tangent); returns (X, p, residual, (dp/ds at a, b,
    there)) or None."""
    d = np.concatenate([b.X - a.X, [b.p - a.p]])
    L = arc.norm(d)
    ta = a.t / arc.norm(a.t)  # unit in the arc's present scale (it may have grown since a)

    def g(s, *_):
        try:
            pt = arc.correct(a.X + s * L * ta[:arc.N], a.p + s * L * ta[arc.N], ta, exact_tangent=True, start=a)
        except (ConvergenceError, np.linalg.LinAlgError, sla.LinAlgWarning, ValueError, RuntimeError):
            return None
        return pt.t[arc.N], pt

    try:
        tb = arc.exact_tangent(b.X, b.p, ta, start=a)
    except (ConvergenceError, np.linalg.LinAlgError, sla.LinAlgWarning, ValueError, RuntimeError):
        return None
    if np.sign(tb[arc.N]) == np.sign(ta[arc.N]):
        return None
    end = (arc.dot(ta, d) / L, tb[arc.N], ArcPoint(b.X, b.p, tb, b.residual, b.iterations))
    # first trial: the turning point of the cubic p(s) matching p and dp/ds (of the hyperplane coordinate s,
    # d s / d arc = ta . t / L) at both ends
    first = _hermite_turn(end[0], a.p, b.p, ta[arc.N] * L, tb[arc.N] * L / arc.dot(ta, tb))
    res = illinois(g, (0.0, ta[arc.N], a), end, ftol=ftol, stol=1e-12, quadratic=True, first=first)
    if res is None:
        return None
    pt = res[1]
    return pt.X, pt.p, pt.residual, (a.t[arc.N], b.t[arc.N], pt.t[arc.N])


def _hermite_turn(h: float, pa: float, pb: float, da: float, db: float) -> float | None:
    """Where the cubic Hermite interpolant of p on [0, h] (values pa, pb, slopes da, db of
    opposite signs) has zero slope: the root in (0, h) of its quadratic derivative; None if
    the data do not give one."""
    A, B, C = 6.0 * (pa - pb) + 3.0 * h * (da + db), -6.0 * (pa - pb) - 4.0 * h * da - 2.0 * h * db, h * da
    roots = np.roots([A, B, C]) if abs(A) > 0 else np.array([-C / B]) if B != 0 else np.array([])
    inside = [float(u.real) for u in roots if abs(u.imag) <= 1e-12 * max(1.0, abs(u)) and 0.0 < u.real < 1.0]
    return inside[0] * h if len(inside) == 1 else None


def refine_crossing(equations, tol: float, a, b, value, bracket, ftol: float):
    """Parameter where a test function vanishes between branch points a and b (bracket: its
    values there): fixed-parameter Newton solves (``equations(X, p)`` -> (R, J) exact, to
    residual ``tol``) from the interpolated bracket solutions, Illinois on ``value(X, p)`` to
    |value| < ftol. Returns (X, p, residual, (test at a, b, there)) or None."""
    def g(s, lo, hi):
        (sa, _, (Xa, _)), (sb, _, (Xb, _)) = lo, hi
        f = (s - sa) / (sb - sa) if sb != sa else 0.5
        p = a.p + s * (b.p - a.p)
        try:  # exact Jacobians: a fixed-parameter Newton far from the corrector's last point
            res = newton(lambda X: equations(X, p), Xa + f * (Xb - Xa), tol=tol, max_iter=12, label="special point",
                         hint="")
        except ConvergenceError:
            return None
        return value(res.x, p), (res.x, res.residual)

    if not np.sign(bracket[0]) * np.sign(bracket[1]) < 0:
        return None  # no sign change to refine (e.g. another multiplier of that kind nearer the circle)
    stol = 1e-12 * max(1.0, abs(a.p), abs(b.p)) / max(abs(b.p - a.p), 1e-300)
    res = illinois(g, (0.0, bracket[0], (a.X, a.residual)), (1.0, bracket[1], (b.X, b.residual)), ftol=ftol,
                   stol=stol, max_iter=30)
    if res is None:
        return None
    s, (X, rn) = res
    p = a.p + s * (b.p - a.p)
    return X, p, rn, (bracket[0], bracket[1], value(X, p))
