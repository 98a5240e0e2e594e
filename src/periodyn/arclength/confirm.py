"""Special points checked against the truncation, then by direct integration of the DAE (or ODE).

On a harmonic-balance branch every point first goes through
``periodyn.arclength.truncation.check_truncation``: the orbit defect is recorded, and a
point whose orbit is unresolved and whose crossing does not persist at more harmonics is
rejected as spurious without integration (the expensive step below is spent only on the
rest). Points that already carry a defect (checked before, e.g. by a study with ``confirm =
"truncation"``) keep that verdict.

A special point found on a harmonic-balance branch is a property of the truncated
equations; a truncation too short for the orbit can put a multiplier crossing where the
DAE has none. :func:`confirm_special_points` checks each point with the monodromy matrix
of a direct integration: from the orbit at the two branch points that bracket the special
point (and at the point itself) one period is integrated with the variational equations
(``periodyn.nonlinear.shooting_solver.ShootingProblem``, the trajectory and its transition matrix
in one batch), and the multipliers of the point's kind are counted outside the unit
circle: real ones near +1 for folds and branch points, real negative ones for period
doublings, complex pairs for Neimark-Sacker points.

Verdict: **confirmed** when the integrated count changes between the bracketing points
(the crossing is bracketed by the DAE itself) or, failing that, when the integrated
multiplier of that kind nearest the unit circle at the point lies within ``tol`` of it
(the crossing lies just outside the bracket); **rejected** otherwise, with the integrated
multipliers in the reason. Each point also reports the shooting residual
(max-norm of the independent states after one period) of the orbit it was integrated from,
which measures how far the harmonic-balance orbit is from a periodic solution of the DAE.
With ``newton`` > 0 the orbits are first corrected by that many shooting Newton updates.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import ConvergenceError, InputError
from ..nonlinear.shooting_solver import ShootingProblem, start_state
from .branch import Branch, SpecialPoint
from .events import KINDS, nearest_of_kind as _nearest, of_kind
from .truncation import check_truncation

__all__ = ["confirm_special_points", "integrated_multipliers"]


def _outside(mu: np.ndarray, kind: str) -> int:
    return int(np.sum(np.abs(of_kind(mu, kind)) > 1.0))


def integrated_multipliers(system, solution, *, rtol: float = 1e-9, newton: int = 0) -> tuple[np.ndarray, float]:
    """(Floquet multipliers (2(n - m),), shooting residual) of the orbit of a PeriodicSolution
    by one period of direct integration with the variational equations (monodromy
    matrix); the residual is the shooting residual max-norm of its start state (m, rad, m/s,
    rad/s), after ``newton`` shooting Newton updates when > 0 (a failed correction keeps
    the orbit as given)."""
    om, P = float(solution.omega), dict(system.parameters, **solution.parameters)
    q, qd = start_state(system, solution, om, P)
    prob = ShootingProblem(system, q, solution.subharmonic, rtol=rtol, atol=0.1 * rtol)
    X = prob.state(q, qd)
    if newton > 0:
        try:
            X = prob.newton(X, om, P, tol=1e3 * rtol, max_iter=newton).x
        except (ConvergenceError, np.linalg.LinAlgError):
            pass
    R, _, _, blocks = prob.evaluate(X, om, P)
    M = blocks[0]
    return np.linalg.eigvals(M), float(np.max(np.abs(R)))


def confirm_special_points(branch: Branch, system=None, *, tol: float = 1e-3, rtol: float = 1e-9, newton: int = 0,
                           types=tuple(KINDS), defect_tol: float = 1e-3, harmonics: int | None = None,
                           window: float = 0.01, integrate: bool = True, progress=None) -> Branch:
    """The branch with every special point checked (module docstring): ``defect`` (IHB
    branches), ``confirmed`` True/False and ``check`` (the reason) set on each.

    system: the DAE (default: the one the branch was computed with; give it for a branch
    loaded from a file); tol: largest distance | |mu| - 1 | of the integrated critical
    multiplier at the point that still confirms it when the bracket shows no crossing;
    rtol: integration tolerance; newton: shooting Newton updates of each orbit before its
    monodromy (0: the harmonic-balance orbit as it is); types: the special-point types to
    check (the others stay unchecked); defect_tol, harmonics, window: the truncation check
    of an IHB branch (``check_truncation``: largest defect of a resolved orbit, H' of the
    re-solve, relative omega window); integrate: False stops after the truncation check
    (its verdicts only); progress: None or a callable (points done, points to
    check)."""
    system = branch.options.get("system") if system is None else system
    if system is None:
        raise InputError("confirming special points needs the DAE: pass system= for a branch loaded from a file")
    if set(types) - set(KINDS):
        raise InputError(f"types must be among {tuple(KINDS)}, got {tuple(types)}")
    if not 0 < tol < 1 or not 0 < rtol < 1e-3:
        raise InputError(f"tol must lie in (0, 1) and rtol in (0, 1e-3), got tol={tol}, rtol={rtol}")
    if system.n != branch.solutions[0].harmonics.shape[1]:
        raise InputError(f"the system has {system.n} coordinates, the branch {branch.solutions[0].harmonics.shape[1]}")
    unchecked = any(np.isnan(sp.defect) for sp in branch.special_points if sp.type in types)
    if branch.solutions[0].method == "ihb" and unchecked:
        branch = check_truncation(branch, system, harmonics=harmonics, defect_tol=defect_tol, window=window,
                                  types=types)
    if not integrate:
        return branch
    cache: dict[int, tuple] = {}

    def at(k):
        if k not in cache:
            cache[k] = integrated_multipliers(system, branch.solutions[k], rtol=rtol, newton=newton)
        return cache[k]

    out, done, todo = [], 0, sum(sp.type in types and not _spurious(sp) for sp in branch.special_points)
    for sp in branch.special_points:
        if sp.type not in types or _spurious(sp):  # not asked for, or rejected by its truncation
            out.append(sp)
            continue
        checked = _check(sp, at(sp.index), at(sp.index + 1), branch, system, tol, rtol, newton)
        out.append(replace(checked, check=f"{checked.check}; {sp.check}" if sp.check else checked.check))
        done += 1
        if progress is not None:
            progress(done, todo)
    return replace(branch, special_points=tuple(out))


def _spurious(sp: SpecialPoint) -> bool:
    return sp.confirmed is False and sp.check.startswith("spurious")


def _check(sp: SpecialPoint, a, b, branch, system, tol, rtol, newton) -> SpecialPoint:
    kind = KINDS[sp.type]
    (mu_a, def_a), (mu_b, def_b) = a, b
    na, nb = _outside(mu_a, kind), _outside(mu_b, kind)
    pa, pb = branch.parameter[sp.index], branch.parameter[sp.index + 1]
    where = f"{'omega' if branch.parameter_name is None else branch.parameter_name}"
    bracket = (f"{kind} multipliers outside the unit circle by direct integration: {na} at {where}={pa:.6g} "
               f"(nearest {_fmt(_nearest(mu_a, kind))}), {nb} at {pb:.6g} (nearest {_fmt(_nearest(mu_b, kind))})")
    defects = f"shooting residuals {def_a:.2g}, {def_b:.2g}"
    if na != nb:
        return replace(sp, confirmed=True, check=f"confirmed: {bracket}; {defects}")
    if sp.solution is None:
        return replace(sp, confirmed=False, check=f"rejected: no crossing in the bracket ({bracket}; {defects}) "
                                                   "and no refined orbit at the point")
    mu_p, def_p = integrated_multipliers(system, sp.solution, rtol=rtol, newton=newton)
    c = _nearest(mu_p, kind)
    dist = abs(abs(c) - 1.0) if np.isfinite(c) else np.inf
    at_point = (f"at the point the nearest is {_fmt(c)} (| |mu| - 1 | = {dist:.2g}, tol {tol:g}; shooting residual "
                f"{def_p:.2g})")
    if dist <= tol:
        return replace(sp, confirmed=True, check=f"confirmed: {at_point}; no crossing inside the bracket ({bracket})")
    return replace(sp, confirmed=False, check=f"rejected: {bracket}, no crossing; {at_point}; {defects}. The "
                                              "harmonic-balance multipliers cross where the DAE's do not: raise the "
                                              "harmonics")


def _fmt(c: complex) -> str:
    if not np.isfinite(c):
        return "none"
    return f"{c.real:.5g}{c.imag:+.5g}j (|mu| {abs(c):.6g})"
