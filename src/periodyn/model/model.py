"""Model container: nodes, elements, masses, loads, boundary conditions and inputs,
compiled once into flat arrays for the kernels.

Nodal coordinates x: every point contributes ``"<point>.x", "<point>.y"`` (m) (and
``"<point>.z"`` in a spatial model), every angle node its own name (rad), every
orientation node of a spatial model ``"<node>.l0" .. "<node>.l3"`` (Euler parameters, see
:mod:`periodyn.model.spatial`), in this order. Deformation modes are named ``"<element>.<mode>"``.
Coordinates q = [q^r, q^d]: inputs q^r (prescribed nodal coordinates or modes, each
``rate * theta`` above its reference value, theta = omega t the crank angle) and dynamic
coordinates q^d (dynamic nodal coordinates, as deviations from their reference value,
then flexible modes in element order).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..kernels.assembly import ModelArrays
from .output_builder import OutputBuilder
from .outputs import OutputMap
from .elements import (FLEXIBLE, FREE, PRESCRIBED, RIGID, IndependentElement,
                       PlanarBeam, PlanarHinge, PlanarTruss, mode_statuses)
from .spatial import SpatialTruss, orientation_coordinates
from .spatial_builder import SpatialBuilder

__all__ = ["Model", "CompiledModel"]


@dataclass(frozen=True, eq=False)
class CompiledModel:
    """A model compiled for the kernels (built once per model).

    arrays: :class:`periodyn.kernels.assembly.ModelArrays`; coordinate_names (n_x,),
    x_reference (n_x,), mode_names (n_modes,), input_names / input_rates (n_r,) with
    q^r = rates * theta, dynamic_names (n_d,), outputs (compiled
    :class:`periodyn.model.outputs.OutputMap`, one per output), independent elements
    (eq. 11-12).
    """

    name: str
    arrays: ModelArrays
    coordinate_names: tuple[str, ...]
    x_reference: np.ndarray
    mode_names: tuple[str, ...]
    input_names: tuple[str, ...]
    input_rates: np.ndarray
    dynamic_names: tuple[str, ...]
    outputs: tuple[OutputMap, ...]
    independent: tuple[tuple[IndependentElement, np.ndarray], ...]
    constraint_labels: tuple[str, ...]
    dimension: int = 2

    @property
    def output_names(self) -> tuple[str, ...]:
        return tuple(o.name for o in self.outputs)

    @property
    def n_coordinates(self) -> int:
        return len(self.coordinate_names)

    @property
    def n_inputs(self) -> int:
        return len(self.input_names)

    @property
    def n_dynamic(self) -> int:
        return len(self.dynamic_names)

    def inputs(self, theta: float) -> np.ndarray:
        """q^r at crank angle theta (rad), (n_r,)."""
        return self.input_rates * float(theta)


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
        self.elements.append(element)
        return element.name

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

    def prescribe(self, name: str, rate: float = 1.0) -> None:
        """Make a nodal coordinate or a mode (``"<element>.<mode>"``) an input
        ``q^r = reference + rate * theta`` with theta = omega t."""
        if name not in set(self._coordinate_names()):
            if name.count(".") != 1 or name.split(".")[0] not in {e.name for e in self.elements}:
                raise InputError(f"prescribe: '{name}' is neither a nodal coordinate ('<point>.x', an angle) "
                                 "nor a mode '<element>.<mode>' of an existing element")
            self._mode(name)
        if name in self.prescribed:
            raise InputError(f"'{name}' is prescribed twice")
        self.prescribed[name] = float(rate)

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
        if name not in set(self._coordinate_names()):
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
        nodal coordinate exactly once in the reference configuration."""
        from ..kinematics import check_constraints, check_inertia

        coords = self._coordinate_names()
        index = {c: i for i, c in enumerate(coords)}
        n_x = len(coords)
        x_ref = np.array([v for p in self.points.values() for v in p] + list(self.angles.values())
                         + [v for o in self.orientations.values() for v in o])
        elements = self.elements + self._spatial_elements()
        # coordinate statuses
        status: dict[str, str] = {}
        for group, label in ((self.fixed, "fixed"), (self.dynamic, "dynamic"),
                             ([c for c in self.prescribed if c in index], PRESCRIBED)):
            for c in group:
                if c in status:
                    raise InputError(f"nodal coordinate '{c}' is both {status[c]} and {label}; choose one")
                status[c] = label
        # modes
        mode_names, mode_status = [], []
        for e in elements:
            for m, st in zip(e.mode_names, e.modes):
                full = f"{e.name}.{m}"
                mode_names.append(full)
                mode_status.append(PRESCRIBED if full in self.prescribed else st)
        input_names = list(self.prescribed)
        dynamic_names = list(self.dynamic) + [m for m, s in zip(mode_names, mode_status) if s == FLEXIBLE]
        q_names = input_names + dynamic_names
        q_index = {c: i for i, c in enumerate(q_names)}
        n_q = len(q_names)

        coord_row = -np.ones(n_x, dtype=np.int64)
        mode_row = -np.ones(len(mode_names), dtype=np.int64)
        rhs0 = np.zeros(n_x)
        rhs_q = np.zeros((n_x, n_q))
        labels = []
        row = 0
        for c in coords:
            if c in status:
                coord_row[index[c]] = row
                rhs0[row] = x_ref[index[c]]
                if c in q_index:
                    rhs_q[row, q_index[c]] = 1.0
                labels.append(f"{status[c]} coordinate '{c}'")
                row += 1
        n_eq = len(status) + sum(s != FREE for s in mode_status)
        if n_eq != n_x:
            dependent = [c for c in coords if c not in status]
            constrained = [m for m, s in zip(mode_names, mode_status) if s != FREE]
            over = n_eq > n_x
            fix = ("make a mode free or remove a fixed/prescribed coordinate" if over
                   else "make a free mode rigid, fix a coordinate or add an input")
            raise InputError(
                f"model '{self.name}' is {'over' if over else 'under'}-constrained: {n_x} nodal coordinates but "
                f"{n_eq} equations ({len(status)} fixed/prescribed/dynamic coordinates + {len(constrained)} "
                f"rigid/prescribed/flexible modes); {fix}. Constrained modes: {constrained}; "
                f"coordinates left to the modes: {dependent}")
        for k, (m, s) in enumerate(zip(mode_names, mode_status)):
            if s == FREE:
                continue
            mode_row[k] = row
            if m in q_index:
                rhs_q[row, q_index[m]] = 1.0
            labels.append(f"{s} mode '{m}'")
            row += 1

        ne = len(elements)
        # local widths: the widest family present in this model (no global padding)
        pars = [el.parameters(x_ref[[index[c] for c in el.coordinates()]]) for el in elements]
        ipars = [el.inertia_parameters(p) for el, p in zip(elements, pars)]
        w_dof = max((len(el.coordinates()) for el in elements), default=1)
        w_mode = max((len(el.mode_names) for el in elements), default=1)
        family = np.zeros(ne, dtype=np.int64)
        dofs = -np.ones((ne, w_dof), dtype=np.int64)
        ndof = np.zeros(ne, dtype=np.int64)
        par = np.zeros((ne, max((p.size for p in pars), default=1)))
        ipar = np.zeros((ne, max((p.size for p in ipars), default=1)))
        modes = -np.ones((ne, w_mode), dtype=np.int64)
        nmode = np.zeros(ne, dtype=np.int64)
        stiff = np.zeros((ne, w_mode, w_mode))
        damp = np.zeros((ne, w_mode, w_mode))
        stress0 = np.zeros((ne, w_mode))
        k0 = 0
        for e, el in enumerate(elements):
            loc = [index[c] for c in el.coordinates()]
            family[e] = el.family
            ndof[e] = len(loc)
            dofs[e, :len(loc)] = loc
            par[e, :pars[e].size] = pars[e]
            ipar[e, :ipars[e].size] = ipars[e]
            l0 = par[e, 0]
            if getattr(el, "has_length", False) and not l0 > 0:
                raise InputError(f"element '{el.name}' has zero length in the reference configuration; move its points apart")
            nm = len(el.mode_names)
            nmode[e] = nm
            modes[e, :nm] = np.arange(k0, k0 + nm)
            constitutive = np.array([mode_status[k0 + i] in (FLEXIBLE, FREE) for i in range(nm)], dtype=float)
            mask = np.outer(constitutive, constitutive)
            stiff[e, :nm, :nm] = el.stiffness_matrix(l0) * mask
            damp[e, :nm, :nm] = el.damping_matrix(l0) * mask
            stress0[e, :nm] = getattr(el, "constant_stress", lambda: np.zeros(nm))() * constitutive
            k0 += nm

        nodal_mass = np.zeros(n_x)
        nodal_force = np.zeros(n_x)
        for p, m in self.point_masses.items():
            for c, g in zip(self._axes, self.gravity):
                nodal_mass[index[f"{p}.{c}"]] += m
                nodal_force[index[f"{p}.{c}"]] += m * g
        for a, J in self.inertias.items():
            nodal_mass[index[a]] += J
        for c, f in self.loads.items():
            nodal_force[index[c]] += f

        arrays = ModelArrays(family, dofs, ndof, par, modes, nmode, stiff, damp, stress0, ipar,
                             np.array(self.gravity, dtype=float), mode_row, coord_row, rhs0, rhs_q,
                             len(input_names), nodal_mass, nodal_force)
        outputs = tuple(OutputMap(o.name, o.kind, np.array([index[c] for c in o.coordinates()], dtype=np.int64),
                                  getattr(o, "reference_length", getattr(o, "scale", 1.0)), getattr(o, "element", -1),
                                  getattr(o, "index", -1), None if o.kind != "body_component"
                                  else np.array(o.direction)) for o in self.outputs)
        independent = tuple((el, np.array([index[c] for c in el.coordinates], dtype=np.int64)) for el in self.independent)
        compiled = CompiledModel(self.name, arrays, tuple(coords), x_ref, tuple(mode_names), tuple(input_names),
                                 np.array([self.prescribed[c] for c in input_names]), tuple(dynamic_names),
                                 outputs, independent, tuple(labels), self.dimension)
        check_constraints(compiled)
        check_inertia(compiled)
        return compiled
