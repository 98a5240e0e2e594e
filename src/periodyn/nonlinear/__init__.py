"""Full non-linear equations of DAE/ODE models in the time domain: the one Newton
(``newton``), the one integrator wrapper and stabilized index-1 integration
(``integrate``), steady state, and shooting with monodromy multipliers."""

from .integrate import TimeHistory, consistent_state, integrate, steady_state
from .newton import NewtonResult, newton
from .shooting import ShootingProblem, shooting

__all__ = ["NewtonResult", "TimeHistory", "integrate", "consistent_state", "newton", "steady_state",
           "ShootingProblem", "shooting"]
