"""The spatial beam as model data: reference geometry -> kernel parameters, material data
-> stiffness, damping and inertia parameters (kernel: :mod:`periodyn.kernels.elements.spatial_beam`).

A beam joins two points (coordinates ``"<p>.x", "<p>.y", "<p>.z"``) and two orientation
nodes (Euler parameters ``"<R>.l0" .. "<R>.l3"``, scalar first, ``(cos(phi/2), sin(phi/2) n)``
for a rotation phi about the unit axis n, body to global); the element's local coordinates
are ``[x_p, lam_p, x_q, lam_q]``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..kernels.elements.layout import FAMILY_SPATIAL_BEAM
from ..kernels.elements.rotation import rotation_matrix

MODE_NAMES = ("elongation", "torsion", "bending_z_p", "bending_z_q", "bending_y_p", "bending_y_q")


def beam_parameters(x_p, lam_p, x_q, lam_q, y_axis, what: str = "spatial beam") -> np.ndarray:
    """Kernel parameters par (19,) = [l0, A_p, A_q] from the reference configuration: node
    positions x (3,) (m), unit Euler parameters lam (4,), and a direction y_axis (3,) not
    along the beam for the sections' y axis (the part of it normal to the beam is used;
    z = x cross y); ``what`` names the beam in error messages."""
    x_p, x_q, y_axis = (np.asarray(v, dtype=float) for v in (x_p, x_q, y_axis))
    if x_p.shape != (3,) or x_q.shape != (3,) or y_axis.shape != (3,):
        raise InputError(f"{what}: node positions and y_axis need 3 components each")
    chord = x_q - x_p
    l0 = float(np.linalg.norm(chord))
    if l0 == 0.0:
        raise InputError(f"{what}: its two nodes coincide (zero length); move one node")
    t1 = chord / l0
    y = y_axis - (y_axis @ t1) * t1
    if np.linalg.norm(y) < 1e-8 * max(1.0, np.linalg.norm(y_axis)):
        raise InputError(f"{what}: y_axis is zero or along the beam; give a direction normal to it")
    t2 = y / np.linalg.norm(y)
    axes = np.array([t1, t2, np.cross(t1, t2)])  # rows: section axes in global coordinates
    par = [l0]
    for lam in (lam_p, lam_q):
        lam = np.asarray(lam, dtype=float)
        if lam.shape != (4,) or abs(lam @ lam - 1.0) > 1e-10:
            raise InputError(f"{what}: Euler parameters {lam} must be 4 numbers of unit norm")
        R = np.empty((3, 3))
        rotation_matrix(lam, R)
        par.extend((axes @ R).ravel())  # row k = R^T t_k
    return np.array(par)


def section_second_moments(polar: float, about_y: float, about_z: float) -> np.ndarray:
    """E (3,) = tr(J)/2 - J for the sections' rotary inertias per length J = (polar, about_y,
    about_z) (kg m): the second moments of mass about the section axes the kernel uses."""
    J = np.array([polar, about_y, about_z], dtype=float)
    return 0.5 * J.sum() - J


@dataclass(frozen=True)
class BeamSection:
    """Cross-section data of a spatial beam: EA (N), GJ, EI_y, EI_z (N m^2; EI_z resists
    bending about the section z axis, in the section's x-y plane), mass_per_length rhoA
    (kg/m), rotary inertias per length polar rhoJ, about y rhoI_y, about z rhoI_z (kg m)."""

    EA: float = 0.0
    GJ: float = 0.0
    EI_y: float = 0.0
    EI_z: float = 0.0
    mass_per_length: float = 0.0
    polar_inertia: float = 0.0
    rotary_inertia_y: float = 0.0
    rotary_inertia_z: float = 0.0

    def __post_init__(self):
        for name, value in vars(self).items():
            if not (isinstance(value, (int, float, np.floating)) and np.isfinite(value) and value >= 0.0):
                raise InputError(f"beam section: {name} = {value!r} must be a finite number >= 0")

    @classmethod
    def solid_circular(cls, radius: float, youngs_modulus: float, poisson_ratio: float, density: float,
                       rotary_inertia: bool = True) -> "BeamSection":
        """Solid round section of radius (m), E (N/m^2), nu, rho (kg/m^3); rotary_inertia
        False drops the sections' rotary inertia about y and z (keeps the polar)."""
        if not (radius > 0 and youngs_modulus > 0 and density >= 0 and -1 < poisson_ratio < 0.5):
            raise InputError(f"solid circular section: need radius > 0, E > 0, rho >= 0, -1 < nu < 0.5; got "
                             f"{radius}, {youngs_modulus}, {density}, {poisson_ratio}")
        area = np.pi * radius**2
        second = np.pi * radius**4 / 4
        shear = youngs_modulus / (2 * (1 + poisson_ratio))
        bend = density * second if rotary_inertia else 0.0
        return cls(youngs_modulus * area, shear * 2 * second, youngs_modulus * second, youngs_modulus * second,
                   density * area, density * 2 * second, bend, bend)


@dataclass(frozen=True)
class SpatialBeam:
    """Spatial Euler-Bernoulli beam between points (p, q) carrying orientation nodes
    (R_p, R_q). Modes (see MODE_NAMES): elongation (m), torsion and four end rotations
    relative to the chord (rad); statuses as for every element. section: BeamSection;
    y_axis: reference direction of the sections' y axis (3,) (its part normal to the
    beam); lumped_rotary: the sections' rotary inertia lumped at the nodes (else
    consistent); kelvin_voigt: Kelvin-Voigt time constants beta (s), one for all modes or
    one per mode (6, equal within each bending pair), ``S_d = diag(beta) S``."""

    name: str
    points: tuple[str, str]
    orientations: tuple[str, str]
    modes: tuple[str, ...]
    section: BeamSection
    y_axis: tuple[float, float, float] = (0.0, 1.0, 0.0)
    lumped_rotary: bool = False
    kelvin_voigt: float | tuple[float, ...] = 0.0

    family = FAMILY_SPATIAL_BEAM
    mode_names = MODE_NAMES

    def __post_init__(self):
        if not isinstance(self.section, BeamSection):
            raise InputError(f"spatial beam '{self.name}': section must be a BeamSection, got {self.section!r}")
        if np.shape(self.y_axis) != (3,) or not np.all(np.isfinite(self.y_axis)):
            raise InputError(f"spatial beam '{self.name}': y_axis needs 3 finite components, got {self.y_axis!r}")
        beta = self._time_constants()
        if beta.shape != (6,) or not (np.all(np.isfinite(beta)) and np.all(beta >= 0)):
            raise InputError(f"spatial beam '{self.name}': kelvin_voigt = {self.kelvin_voigt!r} must be one time "
                             "constant >= 0 (s) or six, one per mode")
        if beta[2] != beta[3] or beta[4] != beta[5]:
            raise InputError(f"spatial beam '{self.name}': the Kelvin-Voigt time constants of a bending pair "
                             f"(modes {MODE_NAMES[2:4]} and {MODE_NAMES[4:6]}) must be equal, got {tuple(beta)}")

    def coordinates(self) -> list[str]:
        names = []
        for point, node in zip(self.points, self.orientations):
            names += [f"{point}.{c}" for c in "xyz"] + [f"{node}.l{i}" for i in range(4)]
        return names

    def parameters(self, x_ref: np.ndarray) -> np.ndarray:
        """par (19,) from the reference local coordinates (14,)."""
        return beam_parameters(x_ref[0:3], x_ref[3:7], x_ref[7:10], x_ref[10:14], self.y_axis,
                               f"spatial beam '{self.name}'")

    def stiffness_matrix(self, l0: float) -> np.ndarray:
        """S (6,6): EA/l0, GJ/l0 and EI/l0 [[4, 2], [2, 4]] per bending plane."""
        sec = self.section
        S = np.zeros((6, 6))
        S[0, 0] = sec.EA / l0
        S[1, 1] = sec.GJ / l0
        pair = np.array([[4.0, 2.0], [2.0, 4.0]]) / l0
        S[2:4, 2:4] = sec.EI_z * pair
        S[4:6, 4:6] = sec.EI_y * pair
        return S

    def damping_matrix(self, l0: float) -> np.ndarray:
        return self._time_constants()[:, None] * self.stiffness_matrix(l0)

    def _time_constants(self) -> np.ndarray:
        beta = np.asarray(self.kelvin_voigt, dtype=float)
        return np.full(6, float(beta)) if beta.ndim == 0 else beta

    def inertia_parameters(self, par: np.ndarray) -> np.ndarray:
        """ipar (24,) of :func:`periodyn.kernels.elements.spatial_beam.inertia`."""
        sec = self.section
        E = section_second_moments(sec.polar_inertia, sec.rotary_inertia_y, sec.rotary_inertia_z)
        return np.concatenate([par, [sec.mass_per_length], E, [1.0 if self.lumped_rotary else 0.0]])
