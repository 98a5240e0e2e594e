"""Slider-crank mechanism with a flexible connecting rod (Schwab & Meijaard 2001,
section 4.2): rigid crank 0.15 m, inextensible connecting rod 0.3 m of two planar beam
elements (4 dynamic degrees of freedom: the end rotations of both elements), EI =
12.72345 N m^2, 0.2225 kg/m for crank and rod, plunger 0.033375 kg, Kelvin-Voigt damping
giving ``damping`` of critical in the rod's first mode with the crank fixed at theta = 0.
Output ``midpoint_deflection``: distance of the rod's midpoint from the line through its
ends, divided by the rod length (dimensionless).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ..errors import InputError
from ..model.linearization import omega_split
from ..model import Model

__all__ = ["slider_crank", "slider_crank_model", "slider_crank_nonlinear", "first_bending_frequency"]

CRANK_LENGTH = 0.15      # m
ROD_LENGTH = 0.3         # m
MASS_PER_LENGTH = 0.2225  # kg/m
PLUNGER_MASS = 0.033375  # kg
EI = 12.72345            # N m^2


def slider_crank_model(kelvin_voigt: float = 0.0, rod_elements: int = 2, rotary_inertia_per_length: float = 0.0):
    """The compiled element model; kelvin_voigt = material damping time constant (s),
    rod_elements = beam elements in the rod (even for the midpoint output),
    rotary_inertia_per_length = rhoI of the rod's sections (kg m; the paper neglects it)."""
    if not isinstance(rod_elements, int) or rod_elements < 1:
        raise InputError(f"rod_elements must be a positive integer, got {rod_elements!r}")
    m = Model(name="slider_crank")
    m.add_point("O", (0.0, 0.0))
    m.add_point("A", (CRANK_LENGTH, 0.0))
    m.add_angle("crank")
    m.add_angle("crank_A")
    m.add_beam("crank", ("O", "A"), ("crank", "crank_A"), mass_per_length=MASS_PER_LENGTH)
    points = ["A"]
    for i in range(1, rod_elements + 1):
        points.append("B" if i == rod_elements else f"R{i}")
        m.add_point(points[-1], (CRANK_LENGTH + ROD_LENGTH * i / rod_elements, 0.0))
    for i in range(rod_elements + 1):
        m.add_angle(f"rod{i}")
    for i in range(rod_elements):
        m.add_beam(f"rod{i + 1}", (points[i], points[i + 1]), (f"rod{i}", f"rod{i + 1}"),
                   modes=("rigid", "flexible", "flexible"), EI=EI, mass_per_length=MASS_PER_LENGTH,
                   kelvin_voigt=kelvin_voigt, rotary_inertia_per_length=rotary_inertia_per_length)
    m.add_mass("B", PLUNGER_MASS)
    m.fix("O")
    m.fix("B.y")
    m.prescribe("crank", rate=1.0)
    if rod_elements % 2 == 0:
        m.add_midpoint_deflection("midpoint_deflection", ("A", "B"), f"R{rod_elements // 2}", ROD_LENGTH)
    return m.compile()


def first_bending_frequency(model) -> float:
    """Lowest undamped eigenfrequency (rad/s) of the linearized model with the crank
    fixed at theta = 0 (the rod pinned at both ends, along the slider axis)."""
    rest = omega_split(model, 1)  # the kernels the sweep's own model loads (linearize's would be one more)
    w2 = scipy.linalg.eigh(rest.stiffness[0, 0], rest.mass[0], eigvals_only=True)
    return float(np.sqrt(w2[0]))


def _kelvin_voigt(damping) -> tuple[float, float]:
    """(omega1, Kelvin-Voigt time constant) giving ``damping`` of critical in the first mode."""
    if not (isinstance(damping, (int, float)) and 0 <= damping < 1):
        raise InputError(f"damping must be a fraction of critical in [0, 1), got {damping!r}")
    omega1 = first_bending_frequency(slider_crank_model(0.0))
    # Kelvin-Voigt S_d = beta S gives modal damping beta * omega / 2 with the crank fixed
    return omega1, 2.0 * damping / omega1


def slider_crank_nonlinear(damping: float = 0.02, rod_elements: int = 2):
    """The full non-linear equations (4) of the slider-crank as a ``periodyn.DAE`` (an ODE
    in the rod's end rotations, ``periodyn.nonlinear.element_dae``); damping as in
    :func:`slider_crank`."""
    from ..nonlinear.elements import element_dae

    _, beta = _kelvin_voigt(damping)
    return element_dae(slider_crank_model(beta, rod_elements), name=f"slider_crank_nonlinear(damping={damping})")


def slider_crank(damping: float = 0.02, samples: int = 64):
    """OmegaSplitModel of the slider-crank; damping = fraction of critical in the rod's
    first mode with the crank fixed (0.01 and 0.02 in the paper); samples = crank
    angles per revolution. metadata["omega1"]: the first bending frequency (rad/s)."""
    omega1, beta = _kelvin_voigt(damping)
    model = slider_crank_model(beta)
    return omega_split(model, samples, name=f"slider_crank(damping={damping})",
                       rebuild=lambda p: slider_crank(damping, p),
                       metadata={"omega1": omega1, "damping": float(damping), "kelvin_voigt": beta})
