"""Element models declared in a study file's ``[model]`` table: structure and type checks
(:func:`check_element_form`) and the model they build (:func:`element_model`, split in
powers of omega by :func:`periodyn.model.linearization.omega_split`; :func:`element_rotor`
for a ``[campbell]`` study).

Planar (``dimension = 2``, the default): ``points`` [x, y], ``angles``, elements of ``type``
beam / truss / hinge, ``masses``, ``inertias``, ``forces``, ``torques``, outputs of ``type``
midpoint_deflection / relative_rotation / coordinate / mode.

Spatial (``dimension = 3``, implied by ``[model.orientations]``): ``points`` [x, y, z],
``orientations`` (values: :mod:`periodyn.studies.element_values`), ``[model.sections.<name>]``,
elements of ``type`` spatial_beam (points, orientations, section, modes, y_axis,
lumped_rotary, kelvin_voigt), truss, hinge (orientations, axis, mode, stiffness, damping,
torque, misalignment), universal_joint (orientations, axes, cross, rotation), rigid_link
(points, orientation); ``[[model.rigid_bodies]]``; outputs of ``type`` body_component /
coordinate / mode. Both: ``[[model.independent]]`` (eq. 11-12: bearings, seals, springs,
dampers, added masses), ``[model.frequencies]`` (reference frequencies omega*, rad/s, for
``[sweep] omega.unit``) and, for a ``[campbell]`` study of a spatial rotor, ``stations``
(see :mod:`periodyn.studies.element_tables`). Everything maps one to one onto the
:class:`periodyn.model.Model` builder methods.

Functions of the driving angle theta (:class:`periodyn.model.driving.AngleFunction`):
an input in ``[model.prescribed]`` is a rate (``crank = 1.0``: theta) or a table
``{ rate, mean, cosines, sines }`` (``rate * theta + mean + sum_k cosines[k-1] cos k theta
+ sines[k-1] sin k theta``) or ``{ rate, samples }`` (values over one turn at
theta_j = 2 pi j / N); a mode is prescribed by its quoted name (``"bearing.rotation" = 1.0``).
A ``[[model.loads]]`` entry puts such a function (without rate) on a nodal coordinate
(``coordinate = "B.x"``) or on a point along a direction (``point = "B"``,
``direction = [1, 0]`` or [x, y, z]), in N or N m.
"""

from __future__ import annotations

import difflib
import functools

from . import element_tables
from .checks import Checker, kind
from .element_values import modes, names, orientation, section, vector
from ..errors import ConvergenceError, InputError
from ..model.linearization import omega_split
from ..model import Model
from ..model.driving import AngleFunction
from ..system import OmegaSplitModel

__all__ = ["element_model", "element_rotor", "declared_model", "check_element_form", "MODEL_FORM_KEYS"]

_PLANAR_ELEMENTS = {
    "beam": (("name", "points", "angles"), ("modes", "EA", "EI", "mass_per_length", "kelvin_voigt")),
    "truss": (("name", "points"), ("mode", "EA", "mass_per_length", "kelvin_voigt")),
    "hinge": (("name", "angles"), ("mode", "stiffness", "damping", "torque")),
}
_SPATIAL_ELEMENTS = {
    "spatial_beam": (("name", "points", "orientations", "section"),
                     ("modes", "y_axis", "lumped_rotary", "kelvin_voigt")),
    "truss": _PLANAR_ELEMENTS["truss"],
    "hinge": (("name", "orientations", "axis"), ("mode", "stiffness", "damping", "torque", "misalignment")),
    "universal_joint": (("name", "orientations", "axes"), ("cross", "rotation")),
    "rigid_link": (("name", "points", "orientation"), ()),
}
_SCALED = ("scale",)
_PLANAR_OUTPUTS = {"midpoint_deflection": (("name", "ends", "mid", "reference_length"), ()),
                   "relative_rotation": (("name", "angles"), ()),
                   "coordinate": (("name", "coordinate"), _SCALED), "mode": (("name", "mode"), _SCALED)}
_SPATIAL_OUTPUTS = {"body_component": (("name", "points", "orientation", "direction"), _SCALED),
                    "coordinate": (("name", "coordinate"), _SCALED), "mode": (("name", "mode"), _SCALED)}
_PLANAR_ONLY = ("angles", "inertias", "torques")
MODEL_FORM_KEYS = ("name", "dimension", "points", "angles", "orientations", "sections", "elements", "masses",
                   "inertias", "rigid_bodies", "forces", "torques", "gravity", "fixed", "prescribed", "dynamic",
                   "outputs", "loads", "independent", "frequencies", "stations")
_FUNCTION_KEYS = ("rate", "mean", "cosines", "sines", "samples")
_LOAD_KEYS = ("coordinate", "point", "direction") + _FUNCTION_KEYS[1:]


def element_model(table: dict, *, name: str = "model", samples: int = 64) -> OmegaSplitModel:
    """OmegaSplitModel of the element model in a validated ``[model]`` table (see the
    module docstring), sampled at ``samples`` crank angles; resamplable. Its metadata
    holds ``[model.frequencies]`` (reference frequencies, rad/s)."""
    try:
        compiled = declared_model(table, name=name).compile()
        return omega_split(compiled, samples, name=name, metadata=dict(table.get("frequencies", {})) or None,
                           rebuild=functools.partial(element_model, table, name=name))
    except ConvergenceError as exc:  # e.g. the kinematics has no solution at some crank angle
        raise InputError(str(exc)) from None


def element_rotor(table: dict, *, name: str = "model"):
    """The :class:`periodyn.rotor.ElementRotor` (for a ``[campbell]`` study) of a validated
    spatial ``[model]`` table with ``stations`` (point names along the shaft) and one input,
    the spin angle."""
    from ..rotor.element_rotor import ElementRotor

    try:
        return ElementRotor.from_model(declared_model(table, name=name).compile(), table["stations"])
    except ConvergenceError as exc:
        raise InputError(str(exc)) from None


def declared_model(table: dict, *, name: str = "model") -> Model:
    """The :class:`periodyn.model.Model` (not compiled) declared by a validated ``[model]``
    table; a step that fails names its table entry (InputError)."""
    m = Model(name=name, dimension=table.get("dimension", 2))
    steps = [(f"point '{k}'", m.add_point, (k, v), {}) for k, v in table.get("points", {}).items()]
    steps += [(f"angle '{k}'", m.add_angle, (k, v), {}) for k, v in table.get("angles", {}).items()]
    steps += element_tables.node_steps(m, table)
    for i, el in enumerate(table.get("elements", [])):
        kind = el["type"]
        kwargs = {k: tuple(v) if k in ("points", "angles", "orientations") else v
                  for k, v in el.items() if k not in ("type", "name")}
        if m.dimension == 3 and kind == "hinge":
            kwargs["angles"] = kwargs.pop("orientations")
        kwargs.update(element_tables.element_arguments(kwargs))
        add = {"beam": m.add_beam, "truss": m.add_truss, "hinge": m.add_hinge, "spatial_beam": m.add_spatial_beam,
               "universal_joint": m.add_universal_joint, "rigid_link": m.add_rigid_link}[kind]
        steps.append((f"[[model.elements]] #{i + 1} ({kind} '{el['name']}')", add, (el["name"],),
                      kwargs))
    steps += [(f"masses.{k}", m.add_mass, (k, v), {}) for k, v in table.get("masses", {}).items()]
    steps += [(f"inertias.{k}", m.add_inertia, (k, v), {}) for k, v in table.get("inertias", {}).items()]
    steps += element_tables.part_steps(m, table)
    steps += [(f"forces.{k}", m.add_force, (k, v), {}) for k, v in table.get("forces", {}).items()]
    steps += [(f"torques.{k}", m.add_torque, (k, v), {}) for k, v in table.get("torques", {}).items()]
    if "gravity" in table:
        steps.append(("gravity", m.set_gravity, (table["gravity"],), {}))
    steps += [(f"fixed '{k}'", m.fix, (k,), {}) for k in table.get("fixed", [])]
    steps += [(f"prescribed.{k}", m.prescribe, (k, _angle_function(v)), {})
              for k, v in table.get("prescribed", {}).items()]
    for i, load in enumerate(table.get("loads", [])):
        target = load.get("coordinate", load.get("point"))
        steps.append((f"[[model.loads]] #{i + 1} ('{target}')", m.add_load, (target, _angle_function(load)),
                      {"direction": load.get("direction")}))
    steps += [(f"dynamic '{k}'", m.make_dynamic, (k,), {}) for k in table.get("dynamic", [])]
    for i, out in enumerate(table.get("outputs", [])):
        steps.append((f"[[model.outputs]] #{i + 1} ('{out['name']}')", *_output_step(m, out)))
    for where, add, args, kwargs in steps:
        try:
            add(*args, **kwargs)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
    return m


def _output_step(m: Model, out: dict):
    """(method, args, kwargs) adding one checked [[model.outputs]] entry."""
    kind, name, scale = out["type"], out["name"], {"scale": out["scale"]} if "scale" in out else {}
    if kind == "midpoint_deflection":
        return m.add_midpoint_deflection, (name, tuple(out["ends"]), out["mid"], out["reference_length"]), {}
    if kind == "relative_rotation":
        return m.add_relative_rotation, (name, tuple(out["angles"])), {}
    if kind == "coordinate":
        return m.add_coordinate_output, (name, out["coordinate"]), scale
    if kind == "mode":
        return m.add_mode_output, (name, out["mode"]), scale
    return m.add_body_component, (name, tuple(out["points"]), out["orientation"], out["direction"]), scale


def check_element_form(check: Checker, model: dict) -> dict:
    """Structure and types of an element-model [model] table (names are checked when built)."""
    check.keys(model, "[model]", MODEL_FORM_KEYS, ("points", "elements"))
    out = {"name": check.string(model.get("name", "model"), "[model] name")}
    dim = check.integer(model.get("dimension", 3 if "orientations" in model else 2), "[model] dimension")
    if dim not in (2, 3):
        check.fail("[model] dimension", f"must be 2 (planar) or 3 (spatial), got {dim!r}")
    if dim == 2 and "orientations" in model:
        check.fail("[model] dimension", "a planar model (dimension = 2) has angles, not [model.orientations]; "
                                        "drop dimension = 2 for a spatial model")
    out["dimension"] = dim
    if dim == 3:
        for key in _PLANAR_ONLY:
            if key in model:
                check.fail(f"[model.{key}]", "is for planar models; a spatial model has [model.orientations] "
                                             "(and [[model.rigid_bodies]] for rotational inertia)")
    nonnegative = functools.partial(check.number, nonnegative=True)
    vec = functools.partial(vector, check, size=dim)
    tables = {"points": vec, "angles": check.number, "masses": nonnegative,
              "inertias": nonnegative, "forces": vec, "torques": check.number,
              "prescribed": functools.partial(_function, check)}
    for key, check_value in tables.items():
        if key in model:
            table = check.table(model[key], f"[model.{key}]")
            out[key] = {k: check_value(v, f"[model.{key}] {k}") for k, v in table.items()}
    if "gravity" in model:
        out["gravity"] = vec(model["gravity"], "[model] gravity")
    for key in ("fixed", "dynamic"):
        if key in model:
            out[key] = names(check, model[key], f"[model] {key}")
    out.update(element_tables.check_tables(check, model, dim))
    if "loads" in model:
        loads = _entries(check, model["loads"], "loads")
        out["loads"] = [_load(check, entry, f"[[model.loads]] #{i + 1}", dim) for i, entry in enumerate(loads)]
    kinds = {"elements": _PLANAR_ELEMENTS if dim == 2 else _SPATIAL_ELEMENTS,
             "outputs": _PLANAR_OUTPUTS if dim == 2 else _SPATIAL_OUTPUTS}
    for key, choices in kinds.items():
        entries = _entries(check, model.get(key, []), key)
        out[key] = [_check_entry(check, entry, f"[[model.{key}]] #{i + 1}", choices, out.get("sections", {}), dim)
                    for i, entry in enumerate(entries)]
    return out


def _entries(check: Checker, entries, key: str) -> list:
    if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
        check.fail(f"[[model.{key}]]", f"must be an array of tables ([[model.{key}]] sections), got {kind(entries)}")
    return entries


def _check_entry(check: Checker, entry: dict, where: str, kinds: dict, sections: dict, dim: int) -> dict:
    """One [[model.elements]] / [[model.outputs]] entry; ``type`` is required when there is
    a choice."""
    if "type" not in entry and len(kinds) > 1:
        check.fail(where, f"missing required key 'type' (one of: {', '.join(kinds)})")
    kind = check.string(entry.get("type", next(iter(kinds))), f"{where} type")
    if kind not in kinds:
        near = difflib.get_close_matches(kind, kinds, n=1, cutoff=0.6)
        model = "planar" if dim == 2 else "spatial"
        check.fail(f"{where} type", f"unknown type '{kind}'; " + (f"did you mean '{near[0]}'? " if near else "")
                   + f"a {model} model has: {', '.join(kinds)}")
    required, optional = kinds[kind]
    check.keys(entry, where, ("type", *required, *optional), required)
    clean = {"type": kind}
    for k, value in entry.items():
        if k != "type":
            clean[k] = _entry_value(check, k, value, f"{where} {k}", kind, sections)
    return clean


def _entry_value(check: Checker, key: str, value, where: str, entry_type: str, sections: dict):
    """One checked value of an element or output entry."""
    if key in ("points", "angles", "ends", "orientations"):
        return names(check, value, where, 2)
    if key in ("name", "mid", "orientation", "cross", "coordinate") or (key == "mode" and entry_type == "mode"):
        return check.string(value, where)
    if key in ("EA", "EI", "mass_per_length", "stiffness", "damping"):
        return check.number(value, where, nonnegative=True)
    if key == "kelvin_voigt":
        if entry_type == "spatial_beam" and isinstance(value, list):
            if len(value) != 6:
                check.fail(where, f"must be one time constant (s) or six, one per mode, got {len(value)}")
            return [check.number(v, f"{where}[{i}]", nonnegative=True) for i, v in enumerate(value)]
        return check.number(value, where, nonnegative=True)
    if key == "torque":
        return check.number(value, where)
    if key in ("reference_length", "scale"):
        return check.number(value, where, positive=True)
    if key in ("mode", "modes", "misalignment"):
        return modes(check, value, where, allow_many=key == "modes")
    if key in ("axis", "y_axis", "direction"):
        v = vector(check, value, where, 3)
        if key != "direction" and not any(v):
            check.fail(where, "is zero; give a direction (any length but zero)")
        return v
    if key == "axes":
        if not isinstance(value, list) or len(value) != 2:
            check.fail(where, f"must be two axes [[x, y, z], [x, y, z]] (the arms of the cross), got {kind(value)}")
        return [vector(check, a, f"{where}[{i}]", 3) for i, a in enumerate(value)]
    if key == "rotation":
        return orientation(check, value, where)
    if key == "section":
        return section(check, value, where, sections)
    return check.boolean(value, where)  # lumped_rotary


def _angle_function(value):
    """A checked rate or function table as the argument of Model.prescribe / add_load."""
    if not isinstance(value, dict):
        return value
    if "samples" in value:
        return AngleFunction.samples(value["samples"], rate=value.get("rate", 0.0))
    return AngleFunction.fourier(value.get("cosines", ()), value.get("sines", ()), mean=value.get("mean", 0.0),
                                 rate=value.get("rate", 0.0))


def _function(check: Checker, value, where: str, *, keys: tuple[str, ...] = _FUNCTION_KEYS):
    """A rate (number) or a function table of the driving angle {rate, mean, cosines, sines}
    or {rate, samples}."""
    if not isinstance(value, dict):
        return check.number(value, where)
    check.keys(value, where, keys)
    out = {k: v for k, v in value.items() if k not in _FUNCTION_KEYS}
    if "samples" in value and any(k in value for k in ("mean", "cosines", "sines")):
        check.fail(where, "give either samples = [...] (values over one turn) or Fourier coefficients "
                          "(mean, cosines, sines), not both")
    for k in ("rate", "mean"):
        if k in value:
            out[k] = check.number(value[k], f"{where} {k}")
    for k in ("cosines", "sines", "samples"):
        if k in value:
            if not isinstance(value[k], list) or (k == "samples" and not value[k]):
                check.fail(f"{where} {k}", f"must be a {'non-empty ' if k == 'samples' else ''}list of numbers, "
                                           f"got {kind(value[k])}")
            out[k] = [check.number(v, f"{where} {k}[{i}]") for i, v in enumerate(value[k])]
    return out


def _load(check: Checker, entry: dict, where: str, dim: int) -> dict:
    """One [[model.loads]] entry: coordinate, or point and direction, and a function table."""
    if ("coordinate" in entry) == ("point" in entry):
        check.fail(where, "give either coordinate = \"<point>.x\" (or an angle) or point = \"<point>\" with a "
                          "direction")
    if "point" in entry and "direction" not in entry:
        check.fail(where, "a load on a point needs direction = [x, y] ([x, y, z] in a spatial model)")
    out = _function(check, entry, where, keys=_LOAD_KEYS)
    if not any(k in entry for k in ("mean", "cosines", "sines", "samples")):
        check.fail(where, "give the load's samples = [...] over one turn or its Fourier coefficients")
    for k in ("coordinate", "point"):
        if k in entry:
            out[k] = check.string(entry[k], f"{where} {k}")
    if "direction" in entry:
        out["direction"] = vector(check, entry["direction"], f"{where} direction", dim)
    return out
