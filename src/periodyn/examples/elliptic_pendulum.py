"""The elliptic pendulum of Schwab & Meijaard (2001, section 4.1) built from elements:
a crank of length r driven at constant speed moves the centre of a pinion of radius r
rolling inside an annulus of radius 2r (pinion angle = -crank angle, imposed by a
hinge between crank and pinion whose relative rotation is prescribed at rate -2); a
rigid pendulum of length l with a point mass is pinned to the pinion at e r from its
centre, so its support point runs on an ellipse with vertical major axis 2(1+e)r.
A viscous damper in the pendulum-pinion hinge gives relative damping zeta.
Dynamic coordinate: the pendulum angle from the down-hanging vertical (rad).
Its linearized coefficients equal eq. (29) times m l^2.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..model.linearization import omega_split
from ..model import Model

__all__ = ["pendulum_from_elements", "elliptic_pendulum_builder", "elliptic_pendulum_model"]


def elliptic_pendulum_model(length: float = 1.0, radius: float = 0.5, eccentricity: float = 0.5,
                            zeta: float = 0.01, g: float = 9.81, mass: float = 1.0):
    """Compiled element model of :func:`elliptic_pendulum_builder` (same arguments)."""
    return elliptic_pendulum_builder(length, radius, eccentricity, zeta, g, mass).compile()


def elliptic_pendulum_builder(length: float = 1.0, radius: float = 0.5, eccentricity: float = 0.5,
                              zeta: float = 0.01, g: float = 9.81, mass: float = 1.0) -> Model:
    """Element model (builder, not compiled): pendulum length l (m), pinion radius r (m),
    eccentricity factor e, relative damping zeta of the isolated pendulum, gravity g
    (m/s^2), bob mass (kg)."""
    for name, value in (("length", length), ("radius", radius), ("g", g), ("mass", mass)):
        if not value > 0:
            raise InputError(f"{name} must be positive, got {value!r}")
    if not 0 < eccentricity < 1:
        raise InputError(f"eccentricity must be in (0, 1) so the pin is inside the pinion, got {eccentricity!r}")
    omega0 = np.sqrt(g / length)
    m = Model(name="elliptic_pendulum")
    m.add_point("O", (0.0, 0.0))                                 # annulus centre
    m.add_point("C", (0.0, -radius))                             # pinion centre
    m.add_point("P", (0.0, -radius * (1.0 + eccentricity)))      # pendulum pin
    m.add_point("B", (0.0, -radius * (1.0 + eccentricity) - length))  # bob
    for angle in ("crank", "crank_C", "pinion", "pinion_P", "pendulum", "pendulum_B"):
        m.add_angle(angle)
    m.add_beam("crank", ("O", "C"), ("crank", "crank_C"))
    m.add_hinge("gear", ("crank_C", "pinion"))
    m.add_beam("pinion", ("C", "P"), ("pinion", "pinion_P"))
    m.add_beam("pendulum", ("P", "B"), ("pendulum", "pendulum_B"))
    m.add_hinge("pin", ("pinion_P", "pendulum"), mode="free",
                damping=2.0 * zeta * omega0 * mass * length**2)
    m.add_mass("B", mass)
    m.set_gravity((0.0, -g))
    m.fix("O")
    m.prescribe("crank", rate=1.0)
    m.prescribe("gear.rotation", rate=-2.0)   # rolling in the annulus of radius 2r
    m.make_dynamic("pendulum")
    return m


def pendulum_from_elements(*, length: float = 1.0, radius: float = 0.5, eccentricity: float = 0.5,
                           zeta: float = 0.01, g: float = 9.81, mass: float = 1.0, samples: int = 32):
    """OmegaSplitModel of the element-built elliptic pendulum, normalised by m l^2 so
    it compares directly with eq. (29); coordinate "pendulum" (rad);
    metadata["omega0"] = sqrt(g/l) (rad/s) as for ``periodyn.examples.pendulum``."""
    model = elliptic_pendulum_model(length, radius, eccentricity, zeta, g, mass)
    split = omega_split(model, samples, name="elliptic_pendulum_from_elements")
    scale = 1.0 / (mass * length**2)
    return type(split).from_samples(
        split.mass * scale, list(split.damping * scale), list(split.stiffness * scale), list(split.force * scale),
        coordinate_names=split.coordinate_names, name=split.name,
        metadata={"omega0": float(np.sqrt(g / length)), "length": length, "radius": radius,
                  "eccentricity": eccentricity, "zeta": zeta, "g": g, "mass": mass},
        rebuild=lambda p: pendulum_from_elements(length=length, radius=radius, eccentricity=eccentricity,
                                                 zeta=zeta, g=g, mass=mass, samples=p))
