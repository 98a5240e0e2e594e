"""periodyn: periodic vibrations, transients and stability of driven mechanisms and rotors.

Data flow: model -> per-sample matrices -> spectra -> harmonic balance / Hill exponents /
averaging transient -> sweep results. See README.md.
"""

from . import examples
from .analysis import PointResult, solve_point
from .errors import ConvergenceError, InputError
from .hb import AliasingWarning, PeriodicSolution, periodic_solution
from .hill import FloquetExponents, characteristic_exponents, hill_exponents
from .results import load
from .sweep import sweep
from .system import OmegaSplitModel, RheoLinear
from .transient import Transient, transient

__version__ = "0.1.0"

__all__ = [
    "AliasingWarning", "ConvergenceError", "FloquetExponents", "InputError", "OmegaSplitModel",
    "PeriodicSolution", "PointResult", "RheoLinear", "Transient", "characteristic_exponents", "examples",
    "hill_exponents", "load", "periodic_solution", "solve_point", "sweep", "transient",
]
