"""Branch switching: at a period-doubling point onto the period-2T branch, at a branch point
(symmetry-breaking pitchfork, transcritical) onto the crossing branch; from IHB and from
shooting branches.

Shooting: the orbit at the special point is the refined shooting state the branch kept
(``options["special_unknowns"]``), not its truncated spectra (at a branch point the
Jacobian is singular, so a start that is not already converged would be thrown off along
the null direction). At a branch point the first predictor is the null vector of the
shooting Jacobian M - I (``point.eigenvector``); at a period doubling the T-orbit is a
fixed point of the 2T map, whose Jacobian M^2 - I is singular along the eigenvector of M
for the multiplier -1: a pitchfork of the 2T problem, left along that eigenvector. Both
vectors are carried from the branch's independent coordinates to those of the new
shooting problem through the full state (q, q').

A branch loaded from a file (``load_branch``) has no problem: given ``system=`` (the system
it was computed for), its problem is rebuilt from the stored options (and, for shooting, the
stored references that fix its independent coordinates), and the special point's stored
unknowns start the switch as the in-memory ones do."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..nonlinear.ihb_fourier import real_coefficients
from ..nonlinear.ihb_solver import IHBProblem
from ..nonlinear.shooting_solver import ShootingProblem
from ..errors import InputError
from ..numerics.spectra import fourier_coefficients, synthesize
from ..stability.monodromy import integrate, monodromy_matrix
from .branch import Branch, SpecialPoint
from .entry import continuation

__all__ = ["switch_branch", "switch_period_doubling"]


def switch_period_doubling(branch: Branch, point: SpecialPoint, p_stop: float, *, amplitude: float = 1e-2,
                           system=None, **kwargs) -> Branch:
    """Follow the period-doubled (period 2T) branch born at a period-doubling ``point`` of
    an IHB or shooting ``branch``, toward parameter ``p_stop`` (shooting: module docstring).

    The T-periodic solution at the point is re-expressed with base frequency omega/2
    (harmonics 2H, only even ones non-zero); the critical Floquet mode (eigenvector of
    the multiplier near -1 of the monodromy of the orbit's linearization, integrated over
    2T and mapped to q by the null-space basis) has only odd harmonics of omega/2 and is
    orthogonal to that branch, so it is the initial tangent of the new branch (the PD
    point is a pitchfork of the 2T problem). amplitude: relative size of the first step
    along the mode. system: the branch's system, for a branch loaded from a file (module
    docstring). kwargs go to :func:`continuation`.
    """
    if point.type != "period-doubling":
        raise InputError(f"point is a {point.type!r}, not a period-doubling point")
    prob, system = _problem(branch, system)
    if isinstance(prob, ShootingProblem):
        return _switch_shooting(branch, prob, system, point, p_stop, 1, kwargs)
    k = point.index if abs(branch.parameter[point.index] - point.parameter) <= abs(
        branch.parameter[point.index + 1] - point.parameter) else point.index + 1
    name = branch.parameter_name
    om = point.omega
    P = branch.solutions[k].parameters if name is None else dict(branch.solutions[k].parameters,
                                                                  **{name: point.parameter})
    # the T-orbit exactly at the bifurcation point, from the refined one when the branch kept it
    X = _special_unknowns(branch, point)
    Xpd = prob.newton(branch.unknowns[k] if X is None else X, om, P, branch.options["tol"]).x
    sol = prob.solution(Xpd, om, P, 0.0, 0)
    H, H2 = prob.H, 2 * prob.H
    cq = np.zeros((2 * H2 + 1, system.n), complex)  # harmonic l of omega -> harmonic 2l of omega/2
    cl = np.zeros((2 * H2 + 1, system.m), complex)
    cq[H2 + 2 * np.arange(-H, H + 1)] = sol.harmonics
    cl[H2 + 2 * np.arange(-H, H + 1)] = sol.lambda_harmonics
    prob2 = IHBProblem(system, H2, kwargs.pop("samples", None), 2 * prob.nu)
    start = replace(sol, harmonics=cq, lambda_harmonics=cl, subharmonic=2 * prob.nu)
    X2 = prob2.from_solution(start)
    # critical Floquet mode: eigenvector of mu ~ -1, integrated over 2T to the 2T sample times
    lin = prob.linearization(Xpd, om, P)
    mu, V = np.linalg.eig(monodromy_matrix(lin.rheo))
    y0 = V[:, int(np.argmin(np.abs(mu + 1)))].real
    t2 = prob2.theta / (om / prob2.nu)
    z = integrate(lin.rheo, y0, t2)[:, :lin.r]
    basis = synthesize(fourier_coefficients(lin.basis), lin.rheo.omega * t2)
    dq = np.einsum("pnr,pr->pn", basis, z)
    dX = prob2.join(real_coefficients(dq, H2), np.zeros((prob2.L, system.m)))
    scale_q = np.sqrt(np.mean(X2[: system.n * prob2.L] ** 2)) or 1.0
    dX *= amplitude * scale_q * np.sqrt(system.n * prob2.L) / max(np.linalg.norm(dX), 1e-300)
    tangent = np.concatenate([dX, [0.0]])
    p_here = om if name is None else P[name]
    omega_arg = (p_here, p_stop) if name is None else om
    param_arg = None if name is None else (name, p_here, p_stop)
    opts = {"stability": branch.options["stability"]} if "stability" in branch.options else {}
    opts.update(kwargs)
    return continuation(system, omega_arg, H2, "ihb", param_arg, initial=start, subharmonic=2 * prob.nu,
                        samples=prob2.p, tangent=tangent, **opts)


def switch_branch(branch: Branch, point: SpecialPoint, p_stop: float, *, side: int = 1, system=None,
                  **kwargs) -> Branch:
    """Follow the branch crossing an IHB or shooting ``branch`` at a branch ``point`` toward
    parameter ``p_stop`` (shooting: module docstring).

    At the branch point the Jacobian of the harmonic balance equations has a null vector
    phi (``point.eigenvector``: the Floquet mode of multiplier +1 in the harmonics) that is
    not the known branch's tangent; the first predictor is (phi, dp = 0), the tangent of
    the new branch of a pitchfork (the new branch is p - p* ~ s^2; for a transcritical
    point the corrector bends the step onto it). The new branch is then traced by the
    usual pseudo-arc-length steps from the orbit at the point; side (+1 or -1) takes the
    first step along +phi or -phi (the two mirror branches of a pitchfork, the two halves of
    a transcritical crossing); system: the branch's system, for a branch loaded from a file
    (module docstring); kwargs go to :func:`continuation` (e.g. ds, the first step).
    """
    if side not in (1, -1):
        raise InputError(f"side must be +1 or -1 (the sign of the first step along the critical vector), got {side!r}")
    if point.type != "branch-point":
        raise InputError(f"point is a {point.type!r}, not a branch point")
    prob, system = _problem(branch, system)
    if isinstance(prob, ShootingProblem):
        return _switch_shooting(branch, prob, system, point, p_stop, side, kwargs)
    if point.solution is None or point.eigenvector is None:
        raise InputError("the branch point was not refined (no orbit or critical eigenvector): continue with a "
                         "smaller ds_max so its refinement converges")
    name = branch.parameter_name
    sol = point.solution
    tangent = np.concatenate([side * point.eigenvector, [0.0]])
    omega_arg = (point.parameter, p_stop) if name is None else point.omega
    param_arg = None if name is None else (name, point.parameter, p_stop)
    opts = {k: branch.options[k] for k in ("stability", "tol", "ds_max", "ds_min", "max_iter") if k in branch.options}
    opts.update(kwargs)
    return continuation(system, omega_arg, prob.H, "ihb", param_arg, initial=sol,
                        subharmonic=prob.nu, samples=prob.p, tangent=tangent, **opts)


def _problem(branch: Branch, system) -> tuple:
    """(problem, system) of an IHB or shooting branch: its own, or rebuilt for a branch
    loaded from a file from ``system`` and the stored options (module docstring)."""
    opts, prob = branch.options, branch.problem
    if prob is not None:
        system = opts["system"]
    elif system is None:
        raise InputError("the branch was loaded from a file and has no problem: pass system= (the system it was "
                         "computed for) to switch from it")
    elif opts.get("method") == "ihb":
        prob = IHBProblem(system, opts["harmonics"], opts["samples"], opts["subharmonic"])
    elif "problem_references" in opts:
        prob = ShootingProblem(system, opts["problem_references"], opts["subharmonic"],
                               samples=opts["shooting_samples"], parameter=branch.parameter_name)
    if not isinstance(prob, (IHBProblem, ShootingProblem)):
        raise InputError("branch switching needs an IHB branch or a shooting branch on the adaptive integrator "
                         "(DOP853), computed in this session or loaded from its file")
    return prob, system


def _special_unknowns(branch: Branch, point: SpecialPoint):
    """The refined unknowns the branch kept for ``point`` (None when not refined)."""
    known = [j for j, sp in enumerate(branch.special_points)
             if (sp.type, sp.index, sp.parameter) == (point.type, point.index, point.parameter)]
    kept = branch.options.get("special_unknowns", ())
    return kept[known[0]] if known and kept else None


def _switch_shooting(branch: Branch, prob, system, point: SpecialPoint, p_stop: float, side: int,
                     kwargs: dict) -> Branch:
    """Shooting continuation from the refined orbit at ``point`` along its critical vector
    (module docstring): the branch point's null vector, or the period doubling's -1
    eigenvector of M on the 2T problem."""
    opts_in, name = branch.options, branch.parameter_name
    X = _special_unknowns(branch, point)
    if X is None:
        raise InputError("the special point was not refined (no orbit): continue with a smaller ds_max so its "
                         "refinement converges, then switch")
    om = point.omega
    P = dict(system.parameters, **point.solution.parameters)
    q, qd = prob.full_state(X, om, P, 0)
    if point.type == "period-doubling":
        mu, V = np.linalg.eig(prob.monodromy(X, om, P))
        v, nu = V[:, int(np.argmin(np.abs(mu + 1)))].real, 2 * prob.nu
    else:
        v, nu = point.eigenvector, prob.nu
    direction = prob._tangent(q, qd, om, P, 0) @ v  # full-state direction (2n,)
    new = ShootingProblem(system, q, nu)  # the partition continuation's own problem will choose
    dX = side * new._select(0, direction)
    opts = {k: opts_in[k] for k in ("tol", "ds_max", "ds_min", "max_iter", "shooting_samples") if k in opts_in}
    opts.update(kwargs)
    omega_arg = (point.parameter, p_stop) if name is None else om
    param_arg = None if name is None else (name, point.parameter, p_stop)
    H = opts_in["harmonics"] * nu // prob.nu
    return continuation(system, omega_arg, H, "shooting", param_arg, initial=(q, qd), subharmonic=nu,
                        tangent=np.concatenate([dX / np.linalg.norm(dX), [0.0]]), **opts)
