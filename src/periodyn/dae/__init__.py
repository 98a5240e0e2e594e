"""DAE/ODE models of driven mechanisms and their periodic solutions by EGA-IHB.

``model`` (the DAE type), ``rigid2d`` (planar rigid-body builder), ``fourier`` (real
coefficient layout, FFT coefficient blocks), ``ihb`` (residual, Jacobian, Newton),
``stability`` (independent-coordinate reduction, Floquet by monodromy and Hill),
``solution`` (the result object).
"""

from .ihb import IHBProblem, ihb
from .model import DAE
from .rigid2d import PlanarSystem
from .solution import PeriodicSolution

__all__ = ["DAE", "PlanarSystem", "IHBProblem", "ihb", "PeriodicSolution"]
