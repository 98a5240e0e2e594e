"""periodyn: periodic vibrations, transients and stability of driven mechanisms and rotors.

Data flow: model -> per-sample matrices -> spectra -> harmonic balance / Hill exponents /
averaging transient -> sweep results. See README.md.
"""

from . import examples
from .analysis import PointResult, solve_point
from .continuation import Branch, SpecialPoint, continuation, switch_period_doubling
from .dae import DAE, ihb
from .errors import ConvergenceError, InputError
from .hb import AliasingWarning, PeriodicSolution, periodic_solution
from .hill import FloquetExponents, characteristic_exponents, hill_exponents
from .nonlinear import shooting
from .results import load
from .sweep import sweep
from .system import OmegaSplitModel, RheoLinear
from .transient import Transient, transient

__version__ = "0.1.0"

__all__ = [
    "AliasingWarning", "Branch", "ConvergenceError", "DAE", "FloquetExponents", "InputError", "OmegaSplitModel",
    "PeriodicSolution", "PointResult", "RheoLinear", "SpecialPoint", "Transient", "characteristic_exponents",
    "continuation", "examples", "hill_exponents", "ihb", "load", "periodic_solution", "shooting", "solve_point",
    "switch_period_doubling", "sweep", "transient",
]
