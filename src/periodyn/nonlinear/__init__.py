"""Full non-linear equations of DAE/ODE models in the time domain: stabilized index-1
integration (``integrate``), steady state, and shooting with monodromy multipliers."""

from .integrate import TimeHistory, consistent_state, integrate, steady_state
from .shooting import ShootingProblem, shooting

__all__ = ["TimeHistory", "integrate", "consistent_state", "steady_state", "ShootingProblem", "shooting"]
