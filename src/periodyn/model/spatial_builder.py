"""Builder methods of :class:`periodyn.model.Model` for spatial models
(``Model(name, dimension=3)``): orientation nodes, spatial beams, universal joints and rigid
bodies.
Trusses and hinges of a spatial model come from ``Model.add_truss`` / ``Model.add_hinge``."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .elements import FREE, RIGID, mode_statuses
from .spatial import (EulerNormalization, RigidBody, RigidLink, SpatialHinge, euler_parameters, orientation_coordinates,
                      unit_axis)
from .spatial_beam import BeamSection, SpatialBeam


class SpatialBuilder:
    """Mixin of Model: the spatial node and element methods."""

    def add_orientation(self, name: str, rotation=None) -> str:
        """An orientation node with reference rotation (body to global): None (identity),
        Euler parameters (4,) (normalized here) or a rotation matrix (3,3). Its coordinates
        are ``"<name>.l0" .. "<name>.l3"``; the normalization is added as the rigid mode
        ``"<name>.normalization"``."""
        self._require_dimension(3, "add_orientation")
        self._new_node(name)
        if rotation is None:
            lam = np.array([1.0, 0.0, 0.0, 0.0])
        else:
            r = np.asarray(rotation, dtype=float)
            if r.shape == (3, 3) and np.all(np.isfinite(r)) and np.allclose(r @ r.T, np.eye(3), atol=1e-9) \
                    and np.linalg.det(r) > 0:
                lam = euler_parameters(r)
            elif r.shape == (4,) and np.all(np.isfinite(r)) and np.linalg.norm(r) > 1e-12:
                lam = r / np.linalg.norm(r)
            else:
                raise InputError(f"orientation '{name}': rotation must be Euler parameters (4,) or a proper "
                                 f"rotation matrix (3,3), got {rotation!r}")
        self.orientations[name] = tuple(float(v) for v in lam)
        return name

    def _spatial_hinge(self, name, orientations, axis, mode, stiffness, damping, torque=0.0, misalignment=RIGID):
        for o in orientations:
            self._check_node(o, self.orientations, f"hinge '{name}'")
        st = mode_statuses(name, (mode, misalignment, misalignment), SpatialHinge.mode_names)
        return self._add(SpatialHinge(name, tuple(orientations), tuple(unit_axis(f"hinge '{name}'", axis)), st,
                                      float(stiffness), float(damping), float(torque)))

    def add_universal_joint(self, name: str, orientations: tuple[str, str], axes, *, cross: str | None = None,
                            rotation=None) -> tuple[str, str, str]:
        """Universal (Cardan/Hooke) joint between orientation nodes (p, q): hinge
        ``"<name>_p"`` about axes[0] between p and a cross node, hinge ``"<name>_q"`` about
        axes[1] between the cross and q; axes (2, 3) in global components in the reference
        configuration, perpendicular. The cross node (default ``"<name>_cross"``) starts at
        ``rotation`` (default p's reference rotation). Both hinge rotations are free
        (prescribe ``"<name>_p.rotation"`` to drive one). Returns (hinge_p, hinge_q, cross)."""
        self._check_node(orientations[0], self.orientations, f"universal joint '{name}'")
        self._check_node(orientations[1], self.orientations, f"universal joint '{name}'")
        if orientations[0] == orientations[1]:
            raise InputError(f"universal joint '{name}' joins orientation node '{orientations[0]}' to itself; a joint "
                             "connects two different nodes: name the other one in orientations")
        a = np.asarray(axes, dtype=float)
        if a.shape != (2, 3):
            raise InputError(f"universal joint '{name}': axes must be two 3-vectors, got {axes!r}")
        ap, aq = (unit_axis(f"universal joint '{name}'", v) for v in a)
        if abs(ap @ aq) > 1e-9:
            raise InputError(f"universal joint '{name}': the two hinge axes must be perpendicular (the arms of "
                             f"the cross), their cosine is {ap @ aq:.3g}")
        cross = cross or f"{name}_cross"
        self.add_orientation(cross, self.orientations[orientations[0]] if rotation is None else rotation)
        hp = self._spatial_hinge(f"{name}_p", (orientations[0], cross), ap, FREE, 0.0, 0.0)
        hq = self._spatial_hinge(f"{name}_q", (cross, orientations[1]), aq, FREE, 0.0, 0.0)
        return hp, hq, cross

    def add_spatial_beam(self, name: str, points: tuple[str, str], orientations: tuple[str, str],
                         section: BeamSection, *, modes=None, y_axis=(0.0, 1.0, 0.0), lumped_rotary: bool = False,
                         kelvin_voigt=0.0) -> str:
        """Spatial beam between points (p, q) carrying orientation nodes (R_p, R_q);
        modes: statuses for (elongation, torsion, bending_z_p, bending_z_q, bending_y_p,
        bending_y_q) as a tuple, a dict by mode name or one string (default all rigid);
        section: :class:`BeamSection`; y_axis: reference direction of the sections' y axis;
        kelvin_voigt: material damping time constant (s), one or one per mode.
        See :class:`periodyn.model.spatial_beam.SpatialBeam`."""
        self._require_dimension(3, "add_spatial_beam")
        for p in points:
            self._check_node(p, self.points, f"spatial beam '{name}'")
        for o in orientations:
            self._check_node(o, self.orientations, f"spatial beam '{name}'")
        st = mode_statuses(name, modes, SpatialBeam.mode_names)
        return self._add(SpatialBeam(name, tuple(points), tuple(orientations), st, section,
                                     tuple(float(v) for v in np.ravel(y_axis)), bool(lumped_rotary),
                                     kelvin_voigt if np.ndim(kelvin_voigt) == 0 else tuple(np.ravel(kelvin_voigt))))

    def add_rigid_link(self, name: str, points: tuple[str, str], orientation: str) -> str:
        """Carry point ``points[1]`` rigidly with point ``points[0]`` and orientation node
        ``orientation`` at their reference offset (three rigid modes)."""
        for p in points:
            self._check_node(p, self.points, f"rigid link '{name}'")
        self._check_node(orientation, self.orientations, f"rigid link '{name}'")
        return self._add(RigidLink(name, tuple(points), orientation))

    def add_rigid_body(self, orientation: str, inertia, *, point: str | None = None, mass: float = 0.0) -> None:
        """Rigid body: inertia tensor (3,3) kg m^2 about its centre of mass in body
        components (the orientation node's frame), and, with ``point`` (its centre of mass),
        ``mass`` (kg) as a point mass there."""
        self._check_node(orientation, self.orientations, "rigid body")
        J = np.asarray(inertia, dtype=float)
        if J.shape != (3, 3) or not np.allclose(J, J.T) or np.any(np.linalg.eigvalsh(0.5 * (J + J.T)) < 0):
            raise InputError(f"rigid body on '{orientation}': inertia must be a symmetric positive semi-definite "
                             f"(3,3) tensor in kg m^2, got {inertia!r}")
        self.body_inertias[orientation] = self.body_inertias.get(orientation, np.zeros((3, 3))) + J
        if point is not None:
            self.add_mass(point, mass)

    def _require_dimension(self, dim: int, what: str) -> None:
        if self.dimension != dim:
            kind = "spatial: Model(name, dimension=3)" if dim == 3 else "planar (dimension=2)"
            raise InputError(f"{what} needs a {kind} model; model '{self.name}' has dimension {self.dimension}")

    def _orientation_fix(self, node: str) -> list[str]:
        """Three of the node's Euler parameters (all but the largest in the reference) to fix
        or make dynamic; the normalization determines the fourth."""
        names = orientation_coordinates(node)
        keep = int(np.argmax(np.abs(self.orientations[node])))
        return [c for i, c in enumerate(names) if i != keep]

    def _spatial_elements(self) -> list:
        """Elements the model adds: one normalization per orientation node, then rigid bodies."""
        return ([EulerNormalization(o) for o in self.orientations]
                + [RigidBody(o, tuple(map(tuple, J))) for o, J in self.body_inertias.items()])
