"""Spatial model data: orientation nodes (Euler parameters), the spatial truss, the
spatial hinge (SPACAR style), the universal joint built from two hinges, and rigid bodies
(kernels: :mod:`periodyn.kernels.elements.spatial_joints`, ``spatial_truss``, ``rigid_body``).

Coordinates of a spatial model: every point ``"<p>.x", "<p>.y", "<p>.z"`` (m), every
orientation node ``"<R>.l0" .. "<R>.l3"`` (Euler parameters, scalar first, body to global),
with the normalization ``lam . lam - 1 = 0`` as the always-rigid mode
``"<R>.normalization"``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..kernels.elements.layout import (FAMILY_EULER_NORMALIZATION, FAMILY_RIGID_BODY, FAMILY_RIGID_LINK,
                              FAMILY_SPATIAL_HINGE, FAMILY_SPATIAL_TRUSS)
from ..kernels.elements.rotation import product, rotation_matrix
from .elements import PlanarTruss

__all__ = ["EulerNormalization", "SpatialTruss", "SpatialHinge", "RigidBody", "RigidLink", "euler_parameters", "axis_angle",
           "orientation_coordinates"]

EULER = ("l0", "l1", "l2", "l3")


def orientation_coordinates(node: str) -> list[str]:
    """Coordinate names of an orientation node's Euler parameters."""
    return [f"{node}.{c}" for c in EULER]


def euler_parameters(R) -> np.ndarray:
    """Unit Euler parameters (4,) with l0 >= 0 of a rotation matrix R (3,3) (Shepperd's
    method: the largest of the four squares first, so it is accurate for any rotation)."""
    R = np.asarray(R, dtype=float)
    t = np.array([np.trace(R), R[0, 0], R[1, 1], R[2, 2]])
    k = int(np.argmax(t))
    lam = np.empty(4)
    if k == 0:
        lam[0] = 0.5 * np.sqrt(1.0 + t[0])
        lam[1:] = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (4.0 * lam[0])
    else:
        i = k - 1
        j, m = (i + 1) % 3, (i + 2) % 3
        lam[1 + i] = 0.5 * np.sqrt(1.0 + 2.0 * R[i, i] - t[0])
        s = 4.0 * lam[1 + i]
        lam[0] = (R[m, j] - R[j, m]) / s
        lam[1 + j] = (R[j, i] + R[i, j]) / s
        lam[1 + m] = (R[m, i] + R[i, m]) / s
    return lam if lam[0] >= 0 else -lam


def axis_angle(axis, angle: float) -> np.ndarray:
    """Euler parameters (4,) of a rotation angle (rad) about axis (3,) (normalized here)."""
    n = np.asarray(axis, dtype=float)
    n = n / np.linalg.norm(n)
    return np.concatenate([[np.cos(0.5 * angle)], np.sin(0.5 * angle) * n])


def _conj(lam):
    return np.array([lam[0], -lam[1], -lam[2], -lam[3]])


def _quat(a, b):
    out = np.empty(4)
    product(np.asarray(a, dtype=float), np.asarray(b, dtype=float), out)
    return out


class _NoConstitutiveLaw:
    """Elements whose modes carry no stiffness or damping of their own and that have no
    inertia (joints, normalizations); a rigid body overrides inertia_parameters."""

    mode_names: tuple[str, ...]

    def stiffness_matrix(self, l0: float) -> np.ndarray:
        return np.zeros((len(self.mode_names),) * 2)

    damping_matrix = stiffness_matrix

    def inertia_parameters(self, par: np.ndarray) -> np.ndarray:
        return np.zeros(0)


class _OnOrientationNode(_NoConstitutiveLaw):
    """Elements of one orientation node ``name``: its Euler parameters, no geometric data."""

    name: str

    def coordinates(self) -> list[str]:
        return orientation_coordinates(self.name)

    def parameters(self, x_ref: np.ndarray) -> np.ndarray:
        return np.zeros(1)


def unit_axis(what: str, axis) -> np.ndarray:
    """axis (3,) normalized; InputError if it is not a finite non-zero 3-vector."""
    a = np.asarray(axis, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)) or not np.linalg.norm(a) > 1e-12:
        raise InputError(f"{what}: the axis must be a finite non-zero 3-vector (x, y, z), got {axis!r}; "
                         "give its direction (any length but zero)")
    return a / np.linalg.norm(a)


@dataclass(frozen=True)
class EulerNormalization(_OnOrientationNode):
    """The normalization ``lam . lam - 1 = 0`` of orientation node ``node`` (one rigid mode);
    added by the model for every orientation node."""

    name: str
    modes: tuple[str] = ("rigid",)

    family = FAMILY_EULER_NORMALIZATION
    mode_names = ("normalization",)


@dataclass(frozen=True)
class SpatialTruss(PlanarTruss):
    """Spatial truss (bar) between points (p, q); one mode, elongation (m). EA (N),
    mass_per_length (kg/m), kelvin_voigt beta (s); the planar truss's data and inertia."""

    family = FAMILY_SPATIAL_TRUSS

    def coordinates(self) -> list[str]:
        return [f"{p}.{c}" for p in self.points for c in "xyz"]

    def parameters(self, x_ref: np.ndarray) -> np.ndarray:
        return np.array([float(np.linalg.norm(x_ref[3:6] - x_ref[0:3]))])


@dataclass(frozen=True)
class SpatialHinge:
    """Spatial hinge between orientation nodes (p, q) about ``axis`` (3,), a unit vector in
    global components in the reference configuration. Modes (rotation, misalignment_2,
    misalignment_3) in rad: the rotation of q relative to p about the axis and two small
    rotations about axes normal to it (see :mod:`periodyn.kernels.elements.spatial_joints`).
    rotational_stiffness (N m/rad) and rotational_damping (N m s/rad) act on the rotation
    when it is free or flexible, with a constant moment ``torque`` (N m) resisting
    positive rotation."""

    name: str
    orientations: tuple[str, str]
    axis: tuple[float, float, float]
    modes: tuple[str, str, str]
    rotational_stiffness: float = 0.0
    rotational_damping: float = 0.0
    torque: float = 0.0

    family = FAMILY_SPATIAL_HINGE
    mode_names = ("rotation", "misalignment_2", "misalignment_3")

    def coordinates(self) -> list[str]:
        return [c for o in self.orientations for c in orientation_coordinates(o)]

    def parameters(self, x_ref: np.ndarray) -> np.ndarray:
        """[c_p, c_q] (8,): hinge frames relative to the nodes, first axis along the axis."""
        a = np.asarray(self.axis, dtype=float)
        # a rotation taking e_x to a: about e_x x a by the angle between them
        normal = np.cross([1.0, 0.0, 0.0], a)
        s, c = np.linalg.norm(normal), a[0]
        if s < 1e-12:
            h = np.array([1.0, 0, 0, 0]) if c > 0 else np.array([0.0, 0, 0, 1])
        else:
            h = axis_angle(normal, np.arctan2(s, c))
        return np.concatenate([_quat(_conj(x_ref[0:4]), h), _quat(_conj(x_ref[4:8]), h)])

    def stiffness_matrix(self, l0: float) -> np.ndarray:
        return np.diag([self.rotational_stiffness, 0.0, 0.0])

    def damping_matrix(self, l0: float) -> np.ndarray:
        return np.diag([self.rotational_damping, 0.0, 0.0])

    def constant_stress(self) -> np.ndarray:
        return np.array([self.torque, 0.0, 0.0])

    def inertia_parameters(self, par: np.ndarray) -> np.ndarray:
        return np.zeros(0)


@dataclass(frozen=True)
class RigidBody(_OnOrientationNode):
    """Rotational inertia of a rigid body on orientation node ``name``: inertia tensor J
    (3,3) kg m^2 about the centre of mass in body components (the node's frame); its
    mass is a point mass on the position node of the centre of mass. No modes."""

    name: str
    inertia: tuple
    modes: tuple = ()

    family = FAMILY_RIGID_BODY
    mode_names = ()

    def inertia_parameters(self, par: np.ndarray) -> np.ndarray:
        return np.asarray(self.inertia, dtype=float).ravel()


@dataclass(frozen=True)
class RigidLink(_NoConstitutiveLaw):
    """Point ``points[1]`` rigidly carried by point ``points[0]`` and orientation node
    ``orientation`` (a crank arm, a yoke): three rigid modes, the global components of
    ``x_b - x_a - R(lam) d`` (m) with the body offset d from the reference."""

    name: str
    points: tuple[str, str]
    orientation: str
    modes: tuple[str, str, str] = ("rigid",) * 3

    family = FAMILY_RIGID_LINK
    mode_names = ("offset_x", "offset_y", "offset_z")

    def coordinates(self) -> list[str]:
        a, b = (([f"{p}.{c}" for c in "xyz"]) for p in self.points)
        return a + orientation_coordinates(self.orientation) + b

    def parameters(self, x_ref: np.ndarray) -> np.ndarray:
        """d (3,) = R(lam)^T (x_b - x_a) in the reference."""
        return rotation_of(x_ref[3:7]).T @ (x_ref[7:10] - x_ref[0:3])


def rotation_of(lam) -> np.ndarray:
    """Rotation matrix (3,3) of Euler parameters lam (4,)."""
    R = np.empty((3, 3))
    rotation_matrix(np.asarray(lam, dtype=float), R)
    return R
