"""Full non-linear equations of DAE/ODE models: the problem type (``problem.DAE``), the one Newton
(``newton``), the one integrator wrapper (``integrate.solve``, explicit or implicit with an
analytic Jacobian) and stabilized index-1 integration (``integrate``), stiff integration of
ODE models (``stiff``), the phase-time flow with variational equations (``flow``: monodromy
columns and parameter sensitivities), steady state, single/multiple shooting with monodromy
multipliers; element models (``elements``) and rheo-linear systems (``linear``) as ODE
problems of the same type; EGA-IHB (``ihb``, with its real coefficient layout ``ihb_fourier``
and sparse Jacobian ``ihb_jacobian``) and the perturbation equations about an orbit in
independent coordinates as a ``periodyn.RheoLinear`` (``orbit_linearization``).

Public names are imported on first use: the time-domain core (``integrate``, ``variational``)
is imported by ``periodyn.timedomain``, which Hill's method and the orbit linearization use
in turn, so loading IHB with the package would close an import cycle."""

from __future__ import annotations

from .._lazy import lazy_package

#: public name -> submodule that defines it
_LAZY = {
    "DAE": "problem", "IHBProblem": "ihb", "ihb": "ihb", "NewtonResult": "newton", "newton": "newton",
    "TimeHistory": "integrate", "integrate": "integrate", "consistent_state": "integrate",
    "steady_state": "integrate", "ShootingProblem": "shooting", "shooting": "shooting",
    "element_dae": "elements", "element_outputs": "elements", "integrate_stiff": "stiff",
    "rheo_linear_dae": "linear", "Flow": "variational", "flow": "variational",
}

__all__ = lazy_package(__name__, _LAZY)
