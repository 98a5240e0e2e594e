"""Full non-linear equations of DAE/ODE models in the time domain: the one Newton
(``newton``), the one integrator wrapper (``integrate.solve``, explicit or implicit with an
analytic Jacobian) and stabilized index-1 integration (``integrate``), the phase-time flow
with variational equations (``flow``: monodromy columns and parameter sensitivities),
steady state, and single/multiple shooting with monodromy multipliers."""

from .integrate import TimeHistory, consistent_state, integrate, steady_state
from .newton import NewtonResult, newton
from .shooting import ShootingProblem, shooting
from .variational import Flow, flow

__all__ = ["NewtonResult", "TimeHistory", "integrate", "consistent_state", "newton", "steady_state",
           "ShootingProblem", "shooting", "Flow", "flow"]
