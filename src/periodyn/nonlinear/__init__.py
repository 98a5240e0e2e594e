"""The full non-linear equations of DAE/ODE models (a :class:`periodyn.DAE`), solved for
periodic orbits: EGA-IHB (``ihb_solver``, with its real coefficient layout ``ihb_fourier``
and sparse Jacobian ``ihb_jacobian``), single/multiple shooting with monodromy multipliers
(``shooting``; ``implicit`` for stiff element models; their option objects in ``options``, ``jacobian_reuse`` for the Broyden
corrector along a continuation); element models as ODE problems (``elements``) and the
perturbation equations about an orbit in independent coordinates as a
:class:`periodyn.RheoLinear` (``orbit_linearization``). The time integration, Newton and
variational flow they use live in :mod:`periodyn.numerics`."""

from .elements import element_dae, element_outputs
from .ihb_solver import IHBProblem, ihb
from .options import IHBOptions, ShootingOptions
from .shooting_solver import ShootingProblem, shooting

__all__ = ["IHBOptions", "IHBProblem", "ShootingOptions", "ShootingProblem", "element_dae", "element_outputs", "ihb",
           "shooting"]
