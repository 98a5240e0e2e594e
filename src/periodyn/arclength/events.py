"""Special points between two branch points: one classifier, one root refinement.

Classification (:func:`classify`): a fold where the parameter component of the tangent,
dp/ds, changes sign; a multiplier crossing of the unit circle typed by the one classifier
of :mod:`periodyn.stability.crossings` (period doubling through -1, Neimark-Sacker for a
complex pair); a crossing of +1 is a branch point (symmetry-breaking pitchfork or
transcritical) while dp/ds keeps its sign (with a sign change of dp/ds it is the fold).
Refinement (:func:`illinois`): the Illinois (modified regula falsi) method on a scalar
indicator g(s) over a bracket s in [0, 1]; folds use g = dp/ds along the arc (each trial
point solved by the corrector), multiplier crossings fixed-parameter Newton solves with
g = :func:`crossing_test` (period doubling, Neimark-Sacker) or :func:`branch_test` (branch
point). One bracket reports each type once: two multipliers of one kind leaving in one step
have one refined location (the test function's root), so a second entry would repeat it.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..stability.crossings import KINDS, classify_crossing, of_kind

__all__ = ["KINDS", "branch_test", "classify", "crossing_test", "illinois", "of_kind", "same_point"]


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


def illinois(g: Callable, a: tuple, b: tuple, *, ftol: float, stol: float, max_iter: int = 40):
    """Root of a scalar indicator bracketed by a = (s_a, g_a, data_a), b = (s_b, g_b, data_b).

    g(s, a, b) -> (g(s), data) or None when the trial point cannot be solved (then None is
    returned); the brackets are passed so a trial can start from their data. Stops when
    |g| < ftol or the bracket is shorter than stol; returns (s, data) of the last trial.
    """
    side = 0
    s, data = None, None
    for _ in range(max_iter):
        (sa, fa, da), (sb, fb, db) = a, b
        s = sa + fa * (sb - sa) / (fa - fb) if fa != fb else 0.5 * (sa + sb)
        res = g(s, a, b)
        if res is None:
            return None
        f, data = res
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
