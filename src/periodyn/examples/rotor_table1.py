"""Rotor with two bearings, a seal and two disks: Schwab & Meijaard (2001), section 4.3
(after Sundararajan & Noah 1998), with the paper's conversion factors."""

from __future__ import annotations

from ..errors import InputError
from ..rotor import Bearing, Rotor, Seal, spatial_rotor

INCH = 0.0254          # m
POUND = 0.45359237     # kg
POUND_FORCE = 4.4482216  # N

TABLE_I_SPEED_RPM = 4000.0
TABLE_I_PRESENT = (  # (whirl, eigenvalue rad/s), the paper's "present" column
    ("forward", -7.97 + 223.62j), ("backward", -45.93 + 226.44j), ("backward", -277.46 + 988.02j),
    ("forward", -205.18 + 1030.30j), ("backward", -44.45 + 1893.45j), ("forward", -45.51 + 1921.67j),
    ("backward", -158.01 + 4232.13j), ("forward", -153.39 + 4302.12j))
TABLE_I_REFERENCE = (  # Sundararajan & Noah (1998), as listed in Table I
    -8.04 + 224.13j, -45.87 + 226.05j, -277.95 + 988.32j, -205.31 + 1031.00j,
    -44.30 + 1893.95j, -45.77 + 1922.70j, -158.48 + 4233.10j, -153.89 + 4305.32j)


def rotor(elements: int = 5, rotary_inertia: bool = True, shaft: str = "rotor"):
    """The compiled rotor of section 4.3: steel shaft 50 in long, 4 in diameter, in
    ``elements`` equal Euler-Bernoulli elements (a multiple of 5 so that stations fall
    at every 10 in); isotropic bearings (100 000 lbf/in) at 0 and 10 in; the seal of
    eq. (30) at 20 in with 6.68 kg of added mass; disks at 40 and 50 in. shaft: "rotor"
    (a RotorModel of rotor shaft elements) or "spatial" (an ElementRotor: the shaft of
    spatial beams spinning at the prescribed speed, the disks rigid bodies, see
    :mod:`periodyn.rotor.element_rotor`)."""
    if shaft not in ("rotor", "spatial"):
        raise InputError(f"shaft must be 'rotor' or 'spatial', got {shaft!r}")
    if not isinstance(elements, int) or elements < 5 or elements % 5:
        raise InputError(f"elements must be a positive multiple of 5 so that stations fall at the bearings, seal and "
                         f"disks; got {elements!r}")
    stiffness = POUND_FORCE / INCH                       # lbf/in -> N/m
    damping = POUND_FORCE / INCH                         # lbf s/in -> N s/m
    r = Rotor("rotor")
    r.add_shaft(0.0, 50 * INCH, outer_diameter=4 * INCH, E=3.0e7 * POUND_FORCE / INCH**2,
                density=0.283 * POUND / INCH**3, elements=elements, rotary_inertia=rotary_inertia)
    for at in (0.0, 10 * INCH):
        r.add_bearing(Bearing(at, kyy=1.0e5 * stiffness, kzz=1.0e5 * stiffness))
    r.add_bearing(Seal(20 * INCH, K=89_542 * stiffness, k=27_028 * stiffness, C=171.42 * damping, c=12.0 * damping))
    r.add_mass(20 * INCH, 6.68)
    disk_mass = 0.028 * POUND_FORCE / INCH               # lbf s^2/in -> kg
    inertia = POUND_FORCE * INCH                         # lbf s^2 in -> kg m^2
    for at in (40 * INCH, 50 * INCH):
        r.add_disk(at, mass=disk_mass, polar=0.224 * inertia, diametral=0.114 * inertia)
    return spatial_rotor(r) if shaft == "spatial" else r.compile()
