"""Periodic solutions of a non-linear problem at given speeds, one Newton solve per speed
(the ``omega = { values = [...] }`` form of a continuation study, :mod:`periodyn.studies.continuation`)."""

from __future__ import annotations

import numpy as np

__all__ = ["solve_at_speeds"]


def solve_at_speeds(system, omega, harmonics: int, method: str = "shooting", *, tol: float | None = None,
                    stability: str | None = "magnus", progress=None, **_continuation_options):
    """Branch of periodic solutions at the speeds omega (k,) rad/s, in that order (module
    docstring). method "shooting": element models on the implicit one-period map, each
    speed started from the harmonic-balance orbit of the model's linearization there
    (``omega_split``, max(64, 4 harmonics + 1) samples); other DAEs with DOP853, each from the
    previous orbit (the first from rest). Spectra of q to ``harmonics`` (from 2 harmonics
    + 1 orbit samples; the implicit map from all its steps). "ihb": EGA-IHB with
    ``harmonics`` from the previous orbit, stability by the orbit-linearization
    ``stability`` method (None: no stability). tol: Newton residual max-norm (default the
    solver's). Continuation-only options (ds_max, max_points, ...) are ignored. A speed
    where Newton fails raises its ConvergenceError (no point is recorded unconverged)."""
    from ..arclength import Branch
    from ..harmonic.balance import periodic_solution
    from ..model.linearization import omega_split
    from ..nonlinear import ihb, shooting
    from ..nonlinear.elements import as_dae

    system = as_dae(system, "solve_at_speeds")
    elements = hasattr(getattr(system, "equations", None), "configurations")
    integrator = "implicit" if elements else "DOP853"
    linear = None
    if elements and method == "shooting":
        linear = omega_split(system.equations.model, max(64, 4 * harmonics + 1))
    kw = {} if tol is None else {"tol": tol}
    solutions, previous = [], None
    for k, w in enumerate(np.asarray(omega, float)):
        if method == "ihb":
            previous = ihb(system, float(w), harmonics, initial=previous, stability=stability, **kw)
        else:
            w = float(w)
            start = previous if linear is None else periodic_solution(linear.at(w), harmonics)
            previous = shooting(system, w, initial=start, integrator=integrator, samples=2 * harmonics + 1, **kw)
        solutions.append(previous)
        if progress is not None:
            progress(k + 1, float(w))
    return Branch.from_solutions(solutions, [s.omega for s in solutions], None, (),
                                 f"solutions at {len(solutions)} given speeds ({method})",
                                 options={"method": method, "integrator": integrator if method == "shooting" else "",
                                          "harmonics": int(harmonics)})
