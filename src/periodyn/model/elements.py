"""Element families as small data: which nodes an element joins, its deformation modes
and its material data. Each family maps to one kernel module in
:mod:`periodyn.kernels` (``family`` id, local coordinate layout, mode names).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..kernels.elements import planar_beam
from ..kernels.elements.layout import FAMILY_PLANAR_BEAM, FAMILY_PLANAR_HINGE, FAMILY_PLANAR_TRUSS

RIGID, FLEXIBLE, FREE, PRESCRIBED = "rigid", "flexible", "free", "prescribed"
MODE_STATUSES = (RIGID, FLEXIBLE, FREE)
"""Statuses a user gives per mode: rigid (constrained to zero), flexible (a dynamic
degree of freedom with its constitutive law), free (follows from the kinematics, keeps
its constitutive law, e.g. a damped hinge). ``prescribed`` is set by Model.prescribe."""


def mode_statuses(name: str, modes, mode_names: tuple[str, ...]) -> tuple[str, ...]:
    """Validated statuses per mode from a tuple, a dict by mode name or one string
    (None: all rigid)."""
    if modes is None:
        return (RIGID,) * len(mode_names)
    if isinstance(modes, str):
        modes = (modes,) * len(mode_names)
    if isinstance(modes, dict):
        unknown = set(modes) - set(mode_names)
        if unknown:
            raise InputError(f"element '{name}' has no mode(s) {sorted(unknown)}; its modes are {list(mode_names)}")
        modes = tuple(modes.get(m, RIGID) for m in mode_names)
    modes = tuple(modes)
    if len(modes) != len(mode_names):
        raise InputError(f"element '{name}' needs {len(mode_names)} mode statuses {list(mode_names)}, got {len(modes)}")
    for m in modes:
        if m not in MODE_STATUSES:
            raise InputError(f"element '{name}': mode status {m!r} unknown; use one of {MODE_STATUSES} "
                             "(use Model.prescribe for an input mode)")
    return modes


@functools.lru_cache(maxsize=None)
def _gauss_integrals(shape_functions, order: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """int_0^1 N_i N_j ds and int_0^1 N_i ds for polynomial shape functions (Gauss-Legendre),
    computed once per family of shape functions (read-only arrays)."""
    s, w = np.polynomial.legendre.leggauss(order)
    s = 0.5 * (s + 1.0)
    w = 0.5 * w
    N = np.array([f(s) for f in shape_functions])  # (k, order)
    mass, weights = (N * w) @ N.T, N @ w
    mass.flags.writeable = weights.flags.writeable = False
    return mass, weights


HERMITE = (lambda s: 1 - 3 * s**2 + 2 * s**3, lambda s: 3 * s**2 - 2 * s**3,
           lambda s: s - 2 * s**2 + s**3, lambda s: -(s**2) + s**3)
LINEAR = (lambda s: 1 - s, lambda s: s)
SECTION_ROTATION = (lambda s: 6 * s - 6 * s**2, lambda s: 1 - 4 * s + 3 * s**2, lambda s: -2 * s + 3 * s**2)


@dataclass(frozen=True)
class PlanarBeam:
    """Planar Euler-Bernoulli beam between points (p, q) with end angles (phi_p, phi_q).

    Modes (elongation, bending_p, bending_q): elongation in m, bending as end rotations
    relative to the chord in rad. EA (N), EI (N m^2), mass_per_length rhoA (kg/m),
    rotary_inertia_per_length rhoI (kg m, rotary inertia of the cross-sections, 0 = none),
    kelvin_voigt: material damping time constant beta (s), S_d = beta S.
    """

    name: str
    points: tuple[str, str]
    angles: tuple[str, str]
    modes: tuple[str, str, str]
    EA: float = 0.0
    EI: float = 0.0
    mass_per_length: float = 0.0
    kelvin_voigt: float = 0.0
    rotary_inertia_per_length: float = 0.0

    family = FAMILY_PLANAR_BEAM
    mode_names = ("elongation", "bending_p", "bending_q")
    has_length = True

    def coordinates(self) -> list[str]:
        p, q = self.points
        return [f"{p}.x", f"{p}.y", self.angles[0], f"{q}.x", f"{q}.y", self.angles[1]]

    def parameters(self, x_ref: np.ndarray) -> np.ndarray:
        """[l0, c_p, c_q] from the reference local coordinates (6,)."""
        dx, dy = x_ref[3] - x_ref[0], x_ref[4] - x_ref[1]
        l0 = float(np.hypot(dx, dy))
        alpha = np.arctan2(dy, dx)
        return np.array([l0, alpha - x_ref[2], alpha - x_ref[5]])

    def stiffness_matrix(self, l0: float) -> np.ndarray:
        S = np.zeros((3, 3))
        S[0, 0] = self.EA / l0
        S[1:, 1:] = self.EI / l0 * np.array([[4.0, 2.0], [2.0, 4.0]])
        return S

    def damping_matrix(self, l0: float) -> np.ndarray:
        return self.kelvin_voigt * self.stiffness_matrix(l0)

    def inertia(self, l0: float) -> tuple[np.ndarray, np.ndarray]:
        mass, weights = _gauss_integrals(HERMITE)
        m = self.mass_per_length * l0
        return m * mass, m * weights

    def rotary(self, l0: float) -> np.ndarray:
        """rhoI l0 int W_i W_j ds for the section-rotation interpolation (3,3), kg m^2."""
        return self.rotary_inertia_per_length * l0 * _gauss_integrals(SECTION_ROTATION)[0]

    def inertia_parameters(self, par: np.ndarray) -> np.ndarray:
        """ipar of :mod:`periodyn.kernels.elements.planar_beam` from par = [l0, c_p, c_q]."""
        mass, weights = self.inertia(par[0])
        return planar_beam.pack_inertia(par, mass, weights, self.rotary(par[0]))


@dataclass(frozen=True)
class PlanarTruss:
    """Planar truss (bar) between points (p, q); one mode, elongation (m).
    EA (N), mass_per_length (kg/m), kelvin_voigt beta (s)."""

    name: str
    points: tuple[str, str]
    modes: tuple[str]
    EA: float = 0.0
    mass_per_length: float = 0.0
    kelvin_voigt: float = 0.0

    family = FAMILY_PLANAR_TRUSS
    mode_names = ("elongation",)
    has_length = True

    def coordinates(self) -> list[str]:
        p, q = self.points
        return [f"{p}.x", f"{p}.y", f"{q}.x", f"{q}.y"]

    def parameters(self, x_ref: np.ndarray) -> np.ndarray:
        return np.array([float(np.hypot(x_ref[2] - x_ref[0], x_ref[3] - x_ref[1]))])

    def stiffness_matrix(self, l0: float) -> np.ndarray:
        return np.array([[self.EA / l0]])

    def damping_matrix(self, l0: float) -> np.ndarray:
        return self.kelvin_voigt * self.stiffness_matrix(l0)

    def inertia_parameters(self, par: np.ndarray) -> np.ndarray:
        """ipar of :mod:`periodyn.kernels.elements.planar_truss`: [mass (2x2), weights (2,)], kg."""
        mass, weights = _gauss_integrals(LINEAR)
        m = self.mass_per_length * par[0]
        return np.concatenate([m * mass.ravel(), m * weights])


@dataclass(frozen=True)
class PlanarHinge:
    """Planar hinge: relative rotation phi_q - phi_p of two angles (rad); rotational
    stiffness (N m/rad), viscous damping (N m s/rad) and a constant moment ``torque``
    (N m) resisting positive rotation."""

    name: str
    angles: tuple[str, str]
    modes: tuple[str]
    rotational_stiffness: float = 0.0
    rotational_damping: float = 0.0
    torque: float = 0.0

    family = FAMILY_PLANAR_HINGE
    mode_names = ("rotation",)

    def coordinates(self) -> list[str]:
        return list(self.angles)

    def parameters(self, x_ref: np.ndarray) -> np.ndarray:
        return np.array([x_ref[1] - x_ref[0]])

    def stiffness_matrix(self, l0: float) -> np.ndarray:
        return np.array([[self.rotational_stiffness]])

    def damping_matrix(self, l0: float) -> np.ndarray:
        return np.array([[self.rotational_damping]])

    def constant_stress(self) -> np.ndarray:
        return np.array([self.torque])

    def inertia_parameters(self, par: np.ndarray) -> np.ndarray:
        """A hinge has no inertia of its own."""
        return np.zeros(0)


@dataclass(frozen=True)
class MidpointDeflection:
    """Output: signed distance of point ``mid`` from the line through ``ends``, divided
    by reference_length (m); dimensionless."""

    name: str
    ends: tuple[str, str]
    mid: str
    reference_length: float

    kind = "midpoint_deflection"

    def coordinates(self) -> list[str]:
        a, b = self.ends
        return [f"{a}.x", f"{a}.y", f"{self.mid}.x", f"{self.mid}.y", f"{b}.x", f"{b}.y"]


@dataclass(frozen=True)
class IndependentElement:
    """An independently modelled element (eq. 11-12 of Schwab & Meijaard): linear
    forces ``f = -K dx - C dx' - M dx'' + force`` on the nodal coordinates ``coordinates``
    (k names), not included in the nominal motion. stiffness: sequence over powers of
    omega of (k,k) (at most 3), damping: at most 2, mass: (k,k), force: (k,) constant.
    Used by rotor bearings and seals."""

    name: str
    coordinates: tuple[str, ...]
    stiffness: tuple[np.ndarray, ...] = ()
    damping: tuple[np.ndarray, ...] = ()
    mass: np.ndarray | None = None
    force: np.ndarray | None = None
