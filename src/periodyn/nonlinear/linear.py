"""A rheo-linear system (``periodyn.RheoLinear``) as an ODE ``periodyn.DAE``, so the
linearized equations can be integrated and shot like the non-linear ones (cross-checks
of harmonic balance by shooting, and the linearized side of the non-linear comparisons).

Form: ``q'' = r(t) - P(t) q' - Q(t) q`` with P = M⁻¹C, Q = M⁻¹K, r = M⁻¹f (the paper's
form 16), each evaluated at any t from its trigonometric interpolation of the samples
(exact when the coefficients are band-limited below the sampling rule).
"""

from __future__ import annotations

import numpy as np

from ..spectra import StackedSpectra

__all__ = ["ode", "rheo_linear_dae"]


def ode(n: int, force, force_jacobians, coordinate_names, name: str):
    """``periodyn.DAE`` of the ODE q'' = force(q, qd, t, omega, params) (unit mass, m = 0)
    from batch callables ``force`` -> (p, n) and ``force_jacobians`` -> two (p, n, n)."""
    from .problem import DAE

    eye = np.eye(n)

    def empty(q, *rest):
        return np.zeros((q.shape[0], 0))

    return DAE.from_batch(
        n=n, m=0, mass=lambda q: np.broadcast_to(eye, (q.shape[0], n, n)), force=force,
        force_jacobians=force_jacobians, constraint=empty,
        constraint_jacobian=lambda q, *rest: np.zeros((q.shape[0], 0, n)),
        constraint_hessian=lambda q, lam, *rest: np.zeros((q.shape[0], n, n)),
        constraint_rates=lambda q, qd, *rest: (empty(q), empty(q)), coordinate_names=coordinate_names, name=name)


def rheo_linear_dae(system, *, name: str = "rheo_linear"):
    """ODE ``periodyn.DAE`` (n = system.n, m = 0, unit mass) of the rheo-linear system at
    its own omega; the omega passed to the solvers must be ``system.omega``. The result
    keeps the system as ``rheo_linear``."""
    S = system.inverse_mass_spectra
    stacked = StackedSpectra(S.damping, S.stiffness, S.force)

    def coefficients(t):
        return stacked.at(system.omega * np.asarray(t, float))

    def force(q, qd, t, omega, P):
        Pt, Qt, rt = coefficients(t)
        return rt - np.einsum("pij,pj->pi", Pt, qd) - np.einsum("pij,pj->pi", Qt, q)

    def force_jacobians(q, qd, t, omega, P):
        Pt, Qt, _ = coefficients(t)
        return -Qt, -Pt

    dae = ode(system.n, force, force_jacobians, system.coordinate_names, name)
    dae.rheo_linear = system  # for shooting(..., method="implicit")
    return dae
