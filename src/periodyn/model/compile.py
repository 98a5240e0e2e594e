"""Compiling a :class:`periodyn.model.Model` once into the flat arrays of the kernels
(:data:`periodyn.kernels.mechanism.constraint_system.ModelArrays`): coordinate statuses and the rows of the
constraint equations ``Phi(x) = rhs0 + rhs_q q``, per-element packed data as wide as the
widest family present (no global padding), nodal masses and forces, compiled outputs and
independent elements. The coordinate and mode conventions are those of
:mod:`periodyn.model.model`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..kernels.mechanism.constraint_system import ModelArrays, arrays_class
from .elements import FLEXIBLE, FREE, PRESCRIBED, IndependentElement
from .outputs import OutputMap

__all__ = ["CompiledModel", "compile_model"]


@dataclass(frozen=True, eq=False)
class CompiledModel:
    """A model compiled for the kernels (built once per model).

    arrays: :class:`periodyn.kernels.mechanism.constraint_system.ModelArrays` (or its planar-only or
    spatial-only twin class of the same fields, :func:`~.constraint_system.arrays_class`); coordinate_names (n_x,),
    x_reference (n_x,), mode_names (n_modes,), input_names / input_rates (n_r,) with
    q^r = rates * theta, dynamic_names (n_d,), outputs (compiled
    :class:`periodyn.model.outputs.OutputMap`, one per output), independent elements
    (eq. 11-12); input_motions: per input an AngleFunction g (q^r = g(theta)) or None
    (``rate * theta``), empty when all are None; angle_loads: (nodal coordinate index,
    weight, AngleFunction) of the loads that vary with theta.
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
    input_motions: tuple = ()
    angle_loads: tuple = ()

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

    @property
    def uniform(self) -> bool:
        """True when every input is ``rate * theta`` and no load varies with theta (the
        constant-speed model of eq. 2)."""
        return not self.input_motions and not self.angle_loads

    def inputs(self, theta: float) -> np.ndarray:
        """q^r at crank angle theta (rad), (n_r,)."""
        if not self.input_motions:
            return self.input_rates * float(theta)
        return self.drive(np.array([float(theta)]))[0][0]

    def drive(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """q^r and its first and second derivatives in theta at angles theta (k,) (rad),
        each (k, n_r); the time rates are omega and omega^2 times the derivatives."""
        theta = np.asarray(theta, dtype=float).reshape(-1)
        q = np.outer(theta, self.input_rates)
        dq = np.repeat(self.input_rates[None], theta.size, axis=0)
        ddq = np.zeros_like(q)
        for i, g in enumerate(self.input_motions):
            if g is not None:
                q[:, i], dq[:, i], ddq[:, i] = g(theta)
        return q, dq, ddq

    def applied_loads(self, theta) -> np.ndarray:
        """Nodal loads that vary with theta at angles theta (k,) (rad): (k, n_x) (N, N m)."""
        theta = np.asarray(theta, dtype=float).reshape(-1)
        f = np.zeros((theta.size, self.n_coordinates))
        for i, weight, g in self.angle_loads:
            f[:, i] += weight * g(theta)[0]
        return f


def compile_model(model) -> CompiledModel:
    """Flatten ``model`` into kernel arrays and check that the constraints determine every
    nodal coordinate exactly once in the reference configuration (and that every dynamic
    coordinate moves mass)."""
    from .kinematics import check_constraints, check_inertia

    coords = model._coordinate_names()
    index = {c: i for i, c in enumerate(coords)}
    x_ref = np.array([v for p in model.points.values() for v in p] + list(model.angles.values())
                     + [v for o in model.orientations.values() for v in o])
    elements = model.elements + model._spatial_elements()
    status = _coordinate_statuses(model, index)
    mode_names, mode_status = [], []
    for e in elements:
        for m, st in zip(e.mode_names, e.modes):
            full = f"{e.name}.{m}"
            mode_names.append(full)
            mode_status.append(PRESCRIBED if full in model.prescribed else st)
    input_names = list(model.prescribed)
    dynamic_names = list(model.dynamic) + [m for m, s in zip(mode_names, mode_status) if s == FLEXIBLE]
    coord_row, mode_row, rhs0, rhs_q, labels = _constraint_rows(model.name, coords, x_ref, status, mode_names,
                                                                mode_status, input_names + dynamic_names)
    family, dofs, ndof, par, ipar, modes, nmode, stiff, damp, stress0 = _element_data(elements, index, x_ref,
                                                                                     mode_status)
    nodal_mass, nodal_force = _nodal_data(model, index)
    arrays = arrays_class(family)(family, dofs, ndof, par, modes, nmode, stiff, damp, stress0, ipar,
                                  np.array(model.gravity, dtype=float), mode_row, coord_row, rhs0, rhs_q,
                                  len(input_names), nodal_mass, nodal_force)
    outputs = tuple(OutputMap(o.name, o.kind, np.array([index[c] for c in o.coordinates()], dtype=np.int64),
                              getattr(o, "reference_length", getattr(o, "scale", 1.0)), getattr(o, "element", -1),
                              getattr(o, "index", -1), None if o.kind != "body_component"
                              else np.array(o.direction)) for o in model.outputs)
    independent = tuple((el, np.array([index[c] for c in el.coordinates], dtype=np.int64)) for el in model.independent)
    compiled = CompiledModel(model.name, arrays, tuple(coords), x_ref, tuple(mode_names), tuple(input_names),
                             np.array([model.prescribed[c] for c in input_names]), tuple(dynamic_names),
                             outputs, independent, tuple(labels), model.dimension,
                             tuple(model.motions.get(c) for c in input_names) if model.motions else (),
                             tuple((index[c], w, f) for c, w, f in model.angle_loads))
    check_constraints(compiled)
    check_inertia(compiled)
    return compiled


def _coordinate_statuses(model, index: dict) -> dict[str, str]:
    """{nodal coordinate: "fixed" | "dynamic" | "prescribed"}; a coordinate given two is refused."""
    status: dict[str, str] = {}
    for group, label in ((model.fixed, "fixed"), (model.dynamic, "dynamic"),
                         ([c for c in model.prescribed if c in index], PRESCRIBED)):
        for c in group:
            if c in status:
                raise InputError(f"nodal coordinate '{c}' is both {status[c]} and {label}; choose one")
            status[c] = label
    return status


def _constraint_rows(name: str, coords: list, x_ref: np.ndarray, status: dict, mode_names: list,
                     mode_status: list, q_names: list) -> tuple:
    """Rows of ``Phi(x) = rhs0 + rhs_q q``: coordinate rows first, then constrained modes.
    Returns coord_row (n_x,), mode_row (n_modes,) (-1: no row), rhs0 (n_x,), rhs_q (n_x, n_q)
    and a label per row; refuses a model whose equations do not number its coordinates."""
    n_x = len(coords)
    q_index = {c: i for i, c in enumerate(q_names)}
    coord_row = -np.ones(n_x, dtype=np.int64)
    mode_row = -np.ones(len(mode_names), dtype=np.int64)
    rhs0 = np.zeros(n_x)
    rhs_q = np.zeros((n_x, len(q_names)))
    labels = []
    row = 0
    for i, c in enumerate(coords):
        if c in status:
            coord_row[i] = row
            rhs0[row] = x_ref[i]
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
            f"model '{name}' is {'over' if over else 'under'}-constrained: {n_x} nodal coordinates but "
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
    return coord_row, mode_row, rhs0, rhs_q, labels


def _element_data(elements: list, index: dict, x_ref: np.ndarray, mode_status: list) -> tuple:
    """Per-element packed arrays, as wide as the widest family present: family, dofs, ndof,
    par, ipar, modes, nmode, stiffness, damping, stress0 (see ModelArrays). Stiffness,
    damping and constant stress act only on flexible and free modes."""
    ne = len(elements)
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
    return family, dofs, ndof, par, ipar, modes, nmode, stiff, damp, stress0


def _nodal_data(model, index: dict) -> tuple[np.ndarray, np.ndarray]:
    """Point masses / rotational inertias (n_x,) and constant nodal forces (n_x,) including
    gravity on the point masses."""
    n_x = len(index)
    nodal_mass = np.zeros(n_x)
    nodal_force = np.zeros(n_x)
    for p, m in model.point_masses.items():
        for c, g in zip(model._axes, model.gravity):
            nodal_mass[index[f"{p}.{c}"]] += m
            nodal_force[index[f"{p}.{c}"]] += m * g
    for a, J in model.inertias.items():
        nodal_mass[index[a]] += J
    for c, f in model.loads.items():
        nodal_force[index[c]] += f
    return nodal_mass, nodal_force
