"""Special points checked against the harmonic truncation, before any integration.

A harmonic-balance orbit solves the Galerkin projection of the DAE onto harmonics <= H; what
the truncation throws away shows in the residual of the DAE itself at times between the
IHB's samples. :func:`orbit_defect` evaluates ``r1 = M q'' + Phi_q^T lambda - f`` of the
truncated series at ``oversample`` times the IHB's sample count and returns its max-norm
relative to the force scale max |f| along the orbit (dimensionless: 0 for an exact orbit,
O(1) when the neglected harmonics carry forces as large as the applied ones).

:func:`check_truncation` attaches the defect to every special point. Where it exceeds
``defect_tol`` the point is a property of an unresolved truncation until shown otherwise:
the branch is continued afresh with H' > H harmonics (default H + 4) from the point's orbit,
zero-padded (from a bracketing orbit when Newton fails there), to both sides over
``omega (1 -+ window)``; the point **persists** when the H' branch has a special point of
the same type in that window whose own orbit is resolved (defect <= ``defect_tol``), and is
**spurious** (``confirmed`` False, with the reason) when it has none, when the ones it has
are unresolved too (neither truncation resolves the orbit), or when Newton at H' converges
from none of these orbits. On a branch over another parameter an unresolved point is
flagged (``confirmed`` False, "unresolved") without the re-solve. Points that are resolved
(small defect) or persist keep ``confirmed`` None: the crossing itself is for
``confirm_special_points`` to confirm by direct integration.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import ConvergenceError, InputError
from ..nonlinear.ihb_solver import IHBProblem, default_samples
from .branch import Branch, SpecialPoint
from .driver import trace_branch
from .events import KINDS

__all__ = ["branch_defects", "orbit_defect", "check_truncation"]


def orbit_defect(system, solution, oversample: int = 4) -> float:
    """max_t |M q'' + Phi_q^T lambda - f|_inf / max_t |f|_inf of a harmonic-balance
    PeriodicSolution, at ``oversample`` x the IHB's default samples of its H."""
    return float(branch_defects(system, [solution], oversample)[0])


def branch_defects(system, solutions, oversample: int = 4, unknowns: np.ndarray | None = None) -> np.ndarray:
    """(k,) orbit defects (:func:`orbit_defect`) of k harmonic-balance PeriodicSolutions of
    one H and subharmonic (the points of a branch), with one oversampled problem; unknowns:
    their IHB unknowns (k, size) at that H (a branch's own), else taken from the solutions."""
    if not isinstance(oversample, (int, np.integer)) or oversample < 1:
        raise InputError(f"oversample must be a positive integer, got {oversample!r}")
    s0 = solutions[0]
    H = (s0.harmonics.shape[0] - 1) // 2
    prob = IHBProblem(system, H, oversample * default_samples(H), s0.subharmonic)
    out = np.empty(len(solutions))
    for k, sol in enumerate(solutions):
        P = dict(system.parameters, **sol.parameters)
        X = prob.from_solution(sol) if unknowns is None else unknowns[k]
        _, r1, _, f = prob.sampled_residual(X, float(sol.omega), P)
        out[k] = np.abs(r1).max() / max(np.abs(f).max(), np.finfo(float).tiny)
    return out


def check_truncation(branch: Branch, system=None, *, harmonics: int | None = None, defect_tol: float = 1e-3,
                     window: float = 0.01, types=tuple(KINDS), progress=None) -> Branch:
    """The branch with the orbit defect on every special point of ``types`` and the
    spurious ones rejected (module docstring).

    system: the DAE (default the branch's own; give it for a branch loaded from a file);
    harmonics: H' of the re-solve (default H + 4); defect_tol: largest defect of a resolved
    orbit; window: relative half-width in omega in which the point must persist at H';
    progress: None or a callable (points done, points to check)."""
    system = branch.options.get("system") if system is None else system
    if system is None:
        raise InputError("checking special points needs the DAE: pass system= for a branch loaded from a file")
    if branch.solutions[0].method != "ihb":
        raise InputError("the truncation check is for harmonic-balance (ihb) branches, not "
                         f"{branch.solutions[0].method} ones")
    H = (branch.solutions[0].harmonics.shape[0] - 1) // 2
    H2 = H + 4 if harmonics is None else int(harmonics)
    if H2 <= H:
        raise InputError(f"harmonics (H') must exceed the branch's H = {H}, got {harmonics}")
    if not 0 < defect_tol or not 0 < window < 0.5:
        raise InputError(f"defect_tol must be > 0 and window in (0, 0.5), got {defect_tol}, {window}")
    out, done, todo = [], 0, sum(sp.type in types for sp in branch.special_points)
    for sp in branch.special_points:
        if sp.type in types:
            sp, done = _check(sp, branch, system, H2, defect_tol, window), done + 1
            if progress is not None:
                progress(done, todo)
        out.append(sp)
    return replace(branch, special_points=tuple(out))


def _check(sp: SpecialPoint, branch: Branch, system, H2: int, defect_tol: float, window: float) -> SpecialPoint:
    orbits = [sp.solution] if sp.solution is not None else list(branch.solutions[sp.index:sp.index + 2])
    defect = max(orbit_defect(system, s) for s in orbits)
    H = (orbits[0].harmonics.shape[0] - 1) // 2
    if defect <= defect_tol:
        return replace(sp, defect=defect, confirmed=None,
                       check=f"resolved: orbit defect {defect:.2g} <= {defect_tol:g} at H = {H}")
    if branch.parameter_name is not None:
        return replace(sp, defect=defect, confirmed=False,
                       check=f"unresolved: orbit defect {defect:.2g} > {defect_tol:g} at H = {H} (the re-solve "
                             f"with more harmonics follows omega, not {branch.parameter_name}): raise the harmonics")
    lo, hi = sp.omega * (1 - window), sp.omega * (1 + window)
    try:
        branches = _local_branches(system, sp, branch, (lo, hi), H2)
    except ConvergenceError as exc:
        return replace(sp, defect=defect, confirmed=False,
                       check=f"spurious: orbit defect {defect:.2g} > {defect_tol:g} at H = {H}, and Newton at H' = "
                             f"{H2} does not converge from its orbit or the bracketing ones, zero-padded (last: "
                             f"residual {exc.residual:.2g} after {exc.iterations} updates): the orbit is not a "
                             "truncation of an H' orbit; raise the harmonics")
    found, ends = [], []
    for br in branches:
        found += [p for p in br.points(sp.type) if lo <= p.omega <= hi]
        ends.append(f"{br.omega.min():.6g}..{br.omega.max():.6g}" +
                    ("" if br.status == "parameter range covered" else f" ({br.status})"))
    span = f"H' = {H2} branch over omega {' and '.join(ends)}"
    if found:
        near = min(found, key=lambda p: (_defect(system, p) > defect_tol, abs(p.omega - sp.omega)))
        there = f"its {sp.type} at {near.omega:.6g} rad/s (defect there {_defect(system, near):.2g})"
        if _defect(system, near) > defect_tol:
            return replace(sp, defect=defect, confirmed=False,
                           check=f"spurious: orbit defect {defect:.2g} > {defect_tol:g} at H = {H}, and the {span} "
                                 f"has {there}, unresolved too: neither truncation resolves the orbit there; raise the "
                                 "harmonics")
        return replace(sp, defect=defect, confirmed=None,
                       check=f"persists: orbit defect {defect:.2g} > {defect_tol:g} at H = {H}, but the {span} has "
                             f"{there}")
    return replace(sp, defect=defect, confirmed=False,
                   check=f"spurious: orbit defect {defect:.2g} > {defect_tol:g} at H = {H}, and the {span} has no "
                         f"crossing of this kind within {100 * window:g} % of {sp.omega:.6g} rad/s: a property of the "
                         "truncated equations; raise the harmonics")


def _defect(system, sp: SpecialPoint) -> float:
    """Orbit defect of a point found on an H' branch (0 when its refinement failed: not held against it)."""
    return 0.0 if sp.solution is None else orbit_defect(system, sp.solution)


def _local_branches(system, sp: SpecialPoint, branch: Branch, window: tuple, H2: int) -> list[Branch]:
    """The H2 branch from the point's orbit (else from a bracketing one) to both ends of the
    window; the residual tolerance is 10x the branch's (crossings are located, not orbits
    to the last digit). Raises the last ConvergenceError when no start converges."""
    o = branch.options
    starts = [(sp.solution, sp.omega)] if sp.solution is not None else []
    starts += [(branch.solutions[k], branch.omega[k]) for k in (sp.index, sp.index + 1)]
    error = None
    for orbit, omega in starts:
        try:
            return [trace_branch(system, (omega, stop), harmonics=H2, initial=orbit, tol=10 * o.get("tol", 1e-8),
                                 stability=o.get("stability", "magnus"), ds_max=min(o.get("ds_max", 0.2), 0.05),
                                 max_points=40) for stop in window]
        except ConvergenceError as exc:
            error = exc
    raise error
