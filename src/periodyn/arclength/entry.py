"""``continuation``: the pseudo-arc-length branch (:func:`driver.trace_branch`) with harmonics
that resolve its orbits and its special points checked as ``ContinuationOptions.confirm``
asks (:func:`confirm.confirm_special_points`: "truncation", the default, runs the truncation
check; True then direct integration as well).

Harmonics of an IHB branch: unless given, the branch is traced with H = ``_H_START`` and
traced again with more until the largest orbit defect along it (``truncation.branch_defects``,
the DAE residual between the samples relative to the force scale) is at most
``DEFECT_TOL``: the next H is the one at which the defect, falling geometrically as between
the last two traces, would reach the tolerance, at least H + 4 and at most 2H, up to
``_H_MAX``. Given harmonics are kept. Either way every point's defect is in
``Branch.defect``, and a branch whose orbits stay unresolved warns (:class:`TruncationWarning`)
and says so in ``options["truncation"]``.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np

from ..numerics.threads import one_thread
from ..errors import ConvergenceError
from .branch import Branch
from .confirm import confirm_special_points
from .driver import trace_branch
from .truncation import branch_defects

__all__ = ["DEFECT_TOL", "TruncationWarning", "continuation"]

DEFECT_TOL = 1e-3  # largest orbit defect of a resolved branch (as check_truncation's defect_tol)
_H_START, _H_MAX = 5, 40  # harmonics of the first trace; most harmonics chosen without being asked


class TruncationWarning(UserWarning):
    """A harmonic-balance branch whose orbits the harmonics do not resolve."""


@one_thread()  # small matrices: one BLAS/Numba thread (numerics.threads)
def continuation(system, omega, harmonics: int | None = None, method: str = "ihb", parameter: tuple | None = None,
                 **kwargs) -> Branch:
    """Response curve of a ``periodyn.DAE`` or an element model by pseudo-arc-length
    continuation -> Branch (arguments and options as :func:`driver.trace_branch`).

    harmonics: H; None chooses it for method "ihb" (module docstring: grown until the orbit
    defect is at most ``DEFECT_TOL`` along the branch) and takes 5 for "shooting" (the
    spectra of its orbits only). The special points are then checked as ``confirm`` asks
    (default "truncation": orbit defect and re-solve with more harmonics)."""
    if method != "ihb":
        branch = trace_branch(system, omega, _H_START if harmonics is None else harmonics, method, parameter, **kwargs)
    elif harmonics is not None:
        branch = _flagged(trace_branch(system, omega, harmonics, method, parameter, **kwargs), chosen=False)
    else:
        branch = _flagged(_resolved(system, omega, parameter, kwargs), chosen=True)
    confirm = branch.options.get("confirm", False)
    return confirm_special_points(branch, integrate=confirm is True) if confirm else branch


def _resolved(system, omega, parameter, kwargs) -> Branch:
    """The IHB branch, with its defects, of the fewest harmonics of the growth rule (module
    docstring) that resolve its orbits, or the last one traced."""
    H, last, branch = _H_START, None, None
    while True:
        try:
            new = trace_branch(system, omega, H, "ihb", parameter, **kwargs)
        except ConvergenceError:
            if branch is None:
                raise
            break  # keep the last branch traced (the caller flags it)
        branch = _with_defects(new)
        worst = float(np.max(branch.defect))
        if worst <= DEFECT_TOL or H >= _H_MAX:
            break
        H, last = _next_harmonics(H, worst, last), (H, worst)
    return branch


def _next_harmonics(H: int, defect: float, last: tuple | None) -> int:
    """H of the next trace: where the defect, falling geometrically from the last trace to
    this one, reaches DEFECT_TOL; at least H + 4, at most 2H and _H_MAX."""
    want = 2 * H
    if last is not None and defect < last[1]:
        rate = (np.log(defect) - np.log(last[1])) / (H - last[0])  # log defect per harmonic (< 0)
        want = H + int(np.ceil(np.log(DEFECT_TOL / defect) / rate))
    return int(min(max(want, H + 4), 2 * H, _H_MAX))


def _with_defects(branch: Branch) -> Branch:
    X = branch.unknowns if branch.unknowns is not None and len(branch.unknowns) == len(branch) else None
    return replace(branch, defect=branch_defects(branch.options["system"], branch.solutions, unknowns=X))


def _flagged(branch: Branch, chosen: bool) -> Branch:
    """The branch with its defects (computed unless present), and, when they exceed
    DEFECT_TOL, a TruncationWarning and ``options["truncation"]`` saying so."""
    if branch.defect is None:
        branch = _with_defects(branch)
    H = branch.options["harmonics"]
    k = int(np.argmax(branch.defect))
    if branch.defect[k] <= DEFECT_TOL:
        note = f"resolved: orbit defect at most {branch.defect[k]:.2g} <= {DEFECT_TOL:g} with H = {H}"
    else:
        how = f"chosen (the last that traced; at most {_H_MAX})" if chosen else "given"
        note = (f"unresolved: orbit defect {branch.defect[k]:.2g} > {DEFECT_TOL:g} at omega = {branch.omega[k]:.6g} "
                f"rad/s with H = {H} harmonics {how}, at {int(np.sum(branch.defect > DEFECT_TOL))} of {len(branch)} "
                "points (Branch.defect): amplitudes and special points there may be properties of the truncation; "
                "raise harmonics" + ("" if chosen else " or leave it out to have it chosen"))
        warnings.warn(note, TruncationWarning, stacklevel=3)
    return replace(branch, options=dict(branch.options, truncation=note))
