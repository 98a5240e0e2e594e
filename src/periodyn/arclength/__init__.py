"""Pseudo-arc-length continuation of periodic solutions and its results.

``palc`` (predictor-corrector, step control), ``events`` (the registry of special points:
one classifier of folds, branch points, period doublings and Neimark-Sacker points, user
events ``Event``, one root refinement), ``branch`` (the columnar
``Branch`` and its netCDF file), ``driver`` (``trace_branch`` for IHB and shooting with
``ContinuationOptions``), ``entry`` (``continuation``: that branch with its special points
checked as asked), ``switching`` (onto the period-doubled branch, or the crossing branch at a
branch point), ``truncation`` (each special point's orbit defect, and the point re-solved with more
harmonics where the orbit is unresolved), ``confirm`` (the truncation check, then the monodromy
of a direct integration).
"""

from .branch import Branch, SpecialPoint, load_branch
from .confirm import confirm_special_points
from .driver import ContinuationOptions
from .entry import continuation
from .events import Event, EventPoint
from .switching import switch_branch, switch_period_doubling
from .truncation import check_truncation, orbit_defect

__all__ = ["Branch", "ContinuationOptions", "Event", "EventPoint", "SpecialPoint", "check_truncation",
           "confirm_special_points", "continuation", "load_branch", "orbit_defect", "switch_branch",
           "switch_period_doubling"]
