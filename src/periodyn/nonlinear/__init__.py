"""Full non-linear equations of DAE/ODE models in the time domain: the one Newton
(``newton``), the one integrator wrapper (``integrate.solve``, explicit or implicit with an
analytic Jacobian) and stabilized index-1 integration (``integrate``), stiff integration of
ODE models (``stiff``), the phase-time flow with variational equations (``flow``: monodromy
columns and parameter sensitivities), steady state, single/multiple shooting with monodromy
multipliers; element models (``elements``) and rheo-linear systems (``linear``) as ODE
problems of the same type."""

from .elements import element_dae, element_outputs
from .integrate import TimeHistory, consistent_state, integrate, steady_state
from .newton import NewtonResult, newton
from .linear import rheo_linear_dae
from .shooting import ShootingProblem, shooting
from .stiff import integrate_stiff
from .variational import Flow, flow

__all__ = ["NewtonResult", "TimeHistory", "integrate", "consistent_state", "newton", "steady_state",
           "ShootingProblem", "shooting", "element_dae", "element_outputs", "integrate_stiff", "rheo_linear_dae",
           "Flow", "flow"]
