"""Model container: nodes, elements, masses, loads, boundary conditions and inputs,
compiled once into flat arrays for the kernels.

Nodal coordinates x: every point contributes ``"<point>.x", "<point>.y"`` (m) (and
``"<point>.z"`` in a spatial model), every angle node its own name (rad), every
orientation node of a spatial model ``"<node>.l0" .. "<node>.l3"`` (Euler parameters, see
:mod:`periodyn.model.spatial`), in this order. Deformation modes are named ``"<element>.<mode>"``.
Coordinates q = [q^r, q^d]: inputs q^r (prescribed nodal coordinates or modes, each
``rate * theta`` or a function g(theta) (:class:`~periodyn.model.driving.AngleFunction`)
above its reference value, theta = omega t the crank angle) and dynamic
coordinates q^d (dynamic nodal coordinates, as deviations from their reference value,
then flexible modes in element order).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from .compile import CompiledModel, compile_model
from .output_builder import OutputBuilder
from .driving import AngleFunction, angle_function
from .elements import FREE, RIGID, IndependentElement, PlanarBeam, PlanarHinge, PlanarTruss, mode_statuses
from .spatial import SpatialTruss, orientation_coordinates
from .spatial_builder import SpatialBuilder

__all__ = ["Model", "CompiledModel"]


@dataclass
class Model(SpatialBuilder, OutputBuilder):
    """Builder of a planar (dimension 2) or spatial (dimension 3) flexible multibody
    model (SI units).

    Typical use: add points/angles (planar) or points/orientations (spatial) with
    reference values, elements (all modes rigid unless told), masses and loads; fix,
    prescribe and make dynamic coordinates; add outputs; then :meth:`compile`.
    Deformations are zero in the reference configuration.
    """

    name: str = "model"
    points: dict[str, tuple[float, float]] = field(default_factory=dict)
    angles: dict[str, float] = field(default_factory=dict)
    elements: list = field(default_factory=list)
    point_masses: dict[str, float] = field(default_factory=dict)
    inertias: dict[str, float] = field(default_factory=dict)
    loads: dict[str, float] = field(default_factory=dict)
    gravity: tuple[float, float] = (0.0, 0.0)
    fixed: list[str] = field(default_factory=list)
    prescribed: dict[str, float] = field(default_factory=dict)
    dynamic: list[str] = field(default_factory=list)
    outputs: list = field(default_factory=list)
    independent: list[IndependentElement] = field(default_factory=list)
    dimension: int = 2
    orientations: dict[str, tuple[float, float, float, float]] = field(default_factory=dict)
    body_inertias: dict[str, np.ndarray] = field(default_factory=dict)
    motions: dict[str, AngleFunction] = field(default_factory=dict)
    angle_loads: list[tuple[str, float, AngleFunction]] = field(default_factory=list)

    def __post_init__(self):
        if self.dimension not in (2, 3):
            raise InputError(f"model '{self.name}': dimension must be 2 (planar) or 3 (spatial), got {self.dimension!r}")
        if len(self.gravity) != self.dimension:
            self.gravity = (0.0,) * self.dimension

    # ------------------------------------------------------------------ nodes
    def add_point(self, name: str, position) -> str:
        """A position node at ``position`` (dimension,) m."""
        self._new_node(name)
        pos = np.asarray(position, dtype=float)
        if pos.shape != (self.dimension,) or not np.all(np.isfinite(pos)):
            raise InputError(f"point '{name}' needs a finite {self.dimension}-D position ({', '.join(self._axes)}) "
                             f"in m, got {position!r}")
        self.points[name] = tuple(float(v) for v in pos)
        return name

    def add_angle(self, name: str, value: float = 0.0) -> str:
        """An orientation node of a planar model with reference angle ``value`` (rad)."""
        self._require_dimension(2, "add_angle")
        self._new_node(name)
        self.angles[name] = float(value)
        return name

    @property
    def _axes(self) -> str:
        return "xyz"[:self.dimension]

    def _new_node(self, name: str) -> None:
        if not isinstance(name, str) or not name or "." in name:
            raise InputError(f"node names must be non-empty strings without '.', got {name!r}")
        if name in self.points or name in self.angles or name in self.orientations:
            raise InputError(f"node '{name}' is defined twice; node names must be unique")

    # ------------------------------------------------------------------ elements
    def _add(self, element):
        if any(e.name == element.name for e in self.elements) or element.name in self.orientations:
            raise InputError(f"element '{element.name}' is defined twice (an orientation node's normalization "
                             "carries the node's name); element names must be unique")
        for c in element.coordinates():
            self._check_coordinate(c, f"element '{element.name}'")
        self._check_degenerate(element)
        self.elements.append(element)
        return element.name

    def _check_degenerate(self, element) -> None:
        """Refuse an element joining a node to itself, one of zero length, and negative or
        non-finite section properties (they would be solved as another system)."""
        what = f"element '{element.name}'"
        for field_name in ("points", "angles", "orientations"):
            nodes = getattr(element, field_name, None)
            if nodes is not None and len(set(nodes)) < len(nodes):
                raise InputError(f"{what} joins {field_name[:-1]} node '{nodes[0]}' to itself; an element connects "
                                 f"two different nodes: name the other one in {field_name}")
        points = getattr(element, "points", None)
        if points is not None and np.allclose(self.points[points[0]], self.points[points[1]], rtol=0.0, atol=0.0):
            raise InputError(f"{what} has zero length: points '{points[0]}' and '{points[1]}' are both at "
                             f"{self.points[points[0]]} m; place them apart")
        for prop in ("EA", "EI", "mass_per_length", "kelvin_voigt", "rotary_inertia_per_length"):
            value = np.asarray(getattr(element, prop, 0.0), dtype=float)  # kelvin_voigt may be one per mode
            if not (np.isfinite(value).all() and (value >= 0).all()):
                raise InputError(f"{what}: {prop} must be finite and >= 0, got {getattr(element, prop)!r}")
        for prop in ("stiffness", "damping", "torque", "rotational_stiffness", "rotational_damping"):
            if not np.isfinite(np.asarray(getattr(element, prop, 0.0), dtype=float)).all():
                raise InputError(f"{what}: {prop} must be finite, got {getattr(element, prop)!r}")

    def add_beam(self, name: str, points: tuple[str, str], angles: tuple[str, str], *, modes=None,
                 EA: float = 0.0, EI: float = 0.0, mass_per_length: float = 0.0,
                 kelvin_voigt: float = 0.0, rotary_inertia_per_length: float = 0.0) -> str:
        """Planar beam; modes: statuses for (elongation, bending_p, bending_q) as a tuple,
        a dict by mode name or one string for all (default all rigid). See PlanarBeam."""
        if self.dimension == 3:
            raise InputError(f"beam '{name}': model '{self.name}' is spatial; use add_spatial_beam(name, points, "
                             "orientations, section, ...) for a spatial beam")
        st = mode_statuses(name, modes, PlanarBeam.mode_names)
        return self._add(PlanarBeam(name, tuple(points), tuple(angles), st, float(EA), float(EI),
                                    float(mass_per_length), float(kelvin_voigt), float(rotary_inertia_per_length)))

    def add_truss(self, name: str, points: tuple[str, str], *, mode: str = RIGID, EA: float = 0.0,
                  mass_per_length: float = 0.0, kelvin_voigt: float = 0.0) -> str:
        """Truss (planar or spatial with the model); mode: status of its elongation."""
        st = mode_statuses(name, (mode,), PlanarTruss.mode_names)
        family = PlanarTruss if self.dimension == 2 else SpatialTruss
        return self._add(family(name, tuple(points), st, float(EA), float(mass_per_length), float(kelvin_voigt)))

    def add_hinge(self, name: str, angles: tuple[str, str], *, mode: str = FREE, stiffness: float = 0.0,
                  damping: float = 0.0, axis=None, torque: float = 0.0, misalignment: str = RIGID) -> str:
        """Hinge between two angle nodes (planar) or two orientation nodes about ``axis``
        (3,) in the reference configuration (spatial; its misalignments are rigid); mode:
        status of the relative rotation (default free: follows from the kinematics, with
        its spring/damper; prescribe ``"<name>.rotation"`` to drive it). torque (N m): a
        constant moment the free/flexible rotation carries besides its spring and damper,
        resisting positive rotation (e.g. a load torque on an output shaft). misalignment
        (spatial): status of the two misalignment modes, rigid for a joint, free for a hinge
        that only measures a relative rotation (a twist output)."""
        if self.dimension == 3:
            return self._spatial_hinge(name, angles, axis, mode, stiffness, damping, torque, misalignment)
        st = mode_statuses(name, (mode,), PlanarHinge.mode_names)
        return self._add(PlanarHinge(name, tuple(angles), st, float(stiffness), float(damping), float(torque)))

    # ------------------------------------------------------------------ masses and loads
    def add_mass(self, point: str, mass: float) -> None:
        """Point mass (kg) at a position node."""
        self._check_node(point, self.points, "point mass")
        if not (np.isfinite(mass) and mass >= 0):
            raise InputError(f"point mass at '{point}': mass must be finite and non-negative (kg), got {mass!r}")
        self.point_masses[point] = self.point_masses.get(point, 0.0) + float(mass)

    def add_inertia(self, angle: str, inertia: float) -> None:
        """Rotational inertia (kg m^2) at an angle node."""
        self._check_node(angle, self.angles, "rotational inertia")
        self.inertias[angle] = self.inertias.get(angle, 0.0) + float(inertia)

    def add_force(self, point: str, force) -> None:
        """Constant force (dimension,) N at a point."""
        self._check_node(point, self.points, "force")
        f = np.asarray(force, dtype=float)
        if f.shape != (self.dimension,):
            raise InputError(f"force at '{point}' must have {self.dimension} components, got {force!r}")
        for c, fc in zip(self._axes, f):
            self.loads[f"{point}.{c}"] = self.loads.get(f"{point}.{c}", 0.0) + float(fc)

    def add_torque(self, angle: str, torque: float) -> None:
        """Constant torque (N m) on an angle node."""
        self._check_node(angle, self.angles, "torque")
        self.loads[angle] = self.loads.get(angle, 0.0) + float(torque)

    def add_load(self, target: str, function, direction=None) -> None:
        """A load given as a function of the driving angle theta (an AngleFunction or a
        callable theta -> (f, f', f''), e.g. ``AngleFunction.samples(table)`` of a piston gas
        force): on a nodal coordinate (``"B.x"``, an angle: N or N m), or on a point along
        ``direction`` (dimension,) (N per unit of direction). It enters the linearized
        equations per sample, with no power of omega."""
        f = angle_function(function, f"load on '{target}'")
        if f.rate != 0.0:
            raise InputError(f"load on '{target}': a load must be periodic in theta, but its function grows by "
                             f"{2 * np.pi * f.rate:.6g} per turn; give its periodic table or coefficients")
        if direction is None:
            if target in self.points:
                raise InputError(f"load on point '{target}': give a direction ({self.dimension} components) or "
                                 f"name one coordinate ('{target}.x')")
            self._check_coordinate(target, f"load on '{target}'")
            self.angle_loads.append((target, 1.0, f))
            return
        self._check_node(target, self.points, "load")
        d = np.asarray(direction, dtype=float)
        if d.shape != (self.dimension,) or not np.isfinite(d).all():
            raise InputError(f"load on point '{target}': direction must be {self.dimension} finite numbers, got "
                             f"{direction!r}")
        self.angle_loads.extend((f"{target}.{c}", float(dc), f) for c, dc in zip(self._axes, d) if dc != 0.0)

    def set_gravity(self, acceleration) -> None:
        """Uniform gravity field (dimension,) m/s^2 acting on point masses and distributed masses."""
        g = np.asarray(acceleration, dtype=float)
        if g.shape != (self.dimension,):
            raise InputError(f"gravity must be a {self.dimension}-vector in m/s^2, got {acceleration!r}")
        self.gravity = tuple(float(v) for v in g)

    # ------------------------------------------------------------------ coordinates
    def fix(self, name: str) -> None:
        """Fix a nodal coordinate (``"A.y"``, an angle name), all coordinates of a point, or
        an orientation node (three of its Euler parameters; the normalization sets the fourth)."""
        for c in self._expand(name):
            self.fixed.append(c)

    def prescribe(self, name: str, rate=1.0) -> None:
        """Make a nodal coordinate or a mode (``"<element>.<mode>"``) an input
        ``q^r = reference + rate * theta`` with theta = omega t, or, with ``rate`` an
        AngleFunction or a callable theta -> (g, g', g''), ``q^r = reference + g(theta)``
        (g periodic plus linear in theta: e.g. ``theta + 0.1 (1 - cos theta)`` for a crank
        speed ``omega (1 + 0.1 sin theta)``)."""
        if name not in set(self._coordinate_names()):
            if name.count(".") != 1 or name.split(".")[0] not in {e.name for e in self.elements}:
                raise InputError(f"prescribe: '{name}' is neither a nodal coordinate ('<point>.x', an angle) "
                                 "nor a mode '<element>.<mode>' of an existing element")
            self._mode(name)
        if name in self.prescribed:
            raise InputError(f"'{name}' is prescribed twice")
        if isinstance(rate, (int, float, np.number)):
            self.prescribed[name] = float(rate)
            return
        motion = angle_function(rate, f"prescribe '{name}'")
        self.prescribed[name] = motion.rate
        self.motions[name] = motion

    def make_dynamic(self, coordinate: str) -> None:
        """Make a nodal coordinate a dynamic degree of freedom (deviation from its reference);
        an orientation node name makes three of its Euler parameters dynamic (all but the
        largest in the reference; the normalization sets the fourth)."""
        if coordinate in self.orientations:
            self.dynamic.extend(self._orientation_fix(coordinate))
            return
        self._check_coordinate(coordinate, "make_dynamic")
        self.dynamic.append(coordinate)

    def add_independent(self, element: IndependentElement) -> None:
        """An independently modelled element (eq. 11-12), added to the linearized equations."""
        for c in element.coordinates:
            self._check_coordinate(c, f"independent element '{element.name}'")
        if len(element.stiffness) > 3 or len(element.damping) > 2:
            raise InputError(f"independent element '{element.name}': stiffness may have at most 3 omega powers "
                             "and damping at most 2, so the linearized equations stay quadratic in omega")
        self.independent.append(element)

    # ------------------------------------------------------------------ checks
    def _check_node(self, name, table, what):
        if name not in table:
            kind = "point" if table is self.points else "angle" if table is self.angles else "orientation"
            raise InputError(f"{what}: unknown {kind} node '{name}'; add it with add_{kind}() first")

    def _coordinate_names(self) -> list[str]:
        """Points' (x, y[, z]) in insertion order, then the angles, then the orientations'
        Euler parameters; matches the reference vector."""
        return ([f"{p}.{c}" for p in self.points for c in self._axes] + list(self.angles)
                + [c for o in self.orientations for c in orientation_coordinates(o)])

    def _check_coordinate(self, name, what):
        """Refuse a name that is no nodal coordinate (without listing them all: a model
        with many elements checks each element's coordinates)."""
        node, _, axis = name.rpartition(".") if isinstance(name, str) else ("", "", "")
        known = (name in self.angles or (node in self.points and axis in self._axes)
                 or (node in self.orientations and name in orientation_coordinates(node)))
        if not known:
            raise InputError(f"{what}: unknown nodal coordinate '{name}'; use '<point>.x', '<point>.y', "
                             "'<point>.z', an angle name or '<orientation>.l0'..'.l3' of an existing node")

    def _expand(self, name):
        if name in self.points:
            return [f"{name}.{c}" for c in self._axes]
        if name in self.orientations:
            return self._orientation_fix(name)
        self._check_coordinate(name, "fix")
        return [name]

    def _mode(self, name):
        el, mode = name.split(".")
        element = next(e for e in self.elements if e.name == el)
        if mode not in element.mode_names:
            raise InputError(f"element '{el}' has no mode '{mode}'; its modes are {list(element.mode_names)}")
        return element, element.mode_names.index(mode)

    # ------------------------------------------------------------------ compile
    def compile(self) -> CompiledModel:
        """Flatten into kernel arrays and check that the constraints determine every
        nodal coordinate exactly once in the reference configuration (see
        :func:`periodyn.model.compile.compile_model`)."""
        return compile_model(self)
