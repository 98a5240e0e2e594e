"""DAE/ODE models of driven mechanisms and their periodic solutions by EGA-IHB.

``model`` (the DAE type), ``rigid2d`` (planar rigid-body builder), ``fourier`` (the real
coefficient layout private to IHB, FFT coefficient blocks), ``ihb`` (residual, Jacobian),
``linearization`` (perturbation equations about an orbit in independent coordinates, as a
``periodyn.RheoLinear``, and their Floquet exponents). Results are
``periodyn.periodic.PeriodicSolution`` (re-exported here).
"""

from ..periodic import PeriodicSolution
from .ihb import IHBProblem, ihb
from .model import DAE
from .rigid2d import PlanarSystem

__all__ = ["DAE", "PlanarSystem", "IHBProblem", "ihb", "PeriodicSolution"]
