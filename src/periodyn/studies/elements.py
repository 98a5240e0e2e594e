"""Element models declared in a sweep file's ``[model]`` table: structure and type checks
(:func:`check_element_form`) and the model they build (:func:`element_model`), split in
powers of omega by :func:`periodyn.model.linearization.omega_split`.

Functions of the driving angle theta (:class:`periodyn.model.driving.AngleFunction`):
an input in ``[model.prescribed]`` is a rate (``crank = 1.0``: theta) or a table
``{ rate, mean, cosines, sines }`` (``rate * theta + mean + sum_k cosines[k-1] cos k theta
+ sines[k-1] sin k theta``) or ``{ rate, samples }`` (values over one turn at
theta_j = 2 pi j / N). A ``[[model.loads]]`` entry puts such a function (without rate) on a
nodal coordinate (``coordinate = "B.x"``) or on a point along a direction
(``point = "B"``, ``direction = [1, 0]``), in N or N m.
"""

from __future__ import annotations

import difflib
import functools

from .checks import Checker, kind
from ..errors import ConvergenceError, InputError
from ..model.linearization import omega_split
from ..model import Model
from ..model.driving import AngleFunction
from ..system import OmegaSplitModel

__all__ = ["element_model", "declared_model", "check_element_form", "MODEL_FORM_KEYS"]

_ELEMENT_KEYS = {
    "beam": (("name", "points", "angles"), ("modes", "EA", "EI", "mass_per_length", "kelvin_voigt")),
    "truss": (("name", "points"), ("mode", "EA", "mass_per_length", "kelvin_voigt")),
    "hinge": (("name", "angles"), ("mode", "stiffness", "damping")),
}
_OUTPUT_KEYS = {"midpoint_deflection": (("name", "ends", "mid", "reference_length"), ())}
MODEL_FORM_KEYS = ("name", "points", "angles", "elements", "masses", "inertias", "forces", "torques", "gravity",
                    "fixed", "prescribed", "dynamic", "outputs", "loads")
_FUNCTION_KEYS = ("rate", "mean", "cosines", "sines", "samples")
_LOAD_KEYS = ("coordinate", "point", "direction") + _FUNCTION_KEYS[1:]


def element_model(table: dict, *, name: str = "model", samples: int = 64) -> OmegaSplitModel:
    """OmegaSplitModel of the element model in a validated ``[model]`` table (see the
    module docstring), sampled at ``samples`` crank angles; resamplable."""
    try:
        compiled = declared_model(table, name=name).compile()
        return omega_split(compiled, samples, name=name,
                           rebuild=functools.partial(element_model, table, name=name))
    except ConvergenceError as exc:  # e.g. the kinematics has no solution at some crank angle
        raise InputError(str(exc)) from None


def declared_model(table: dict, *, name: str = "model") -> Model:
    """The :class:`periodyn.model.Model` (not compiled) declared by a validated ``[model]``
    table; a step that fails names its table entry (InputError)."""
    m = Model(name=name)
    steps = [(f"point '{k}'", m.add_point, (k, v), {}) for k, v in table.get("points", {}).items()]
    steps += [(f"angle '{k}'", m.add_angle, (k, v), {}) for k, v in table.get("angles", {}).items()]
    for i, el in enumerate(table.get("elements", [])):
        kind, props = el["type"], {k: v for k, v in el.items() if k not in ("type", "name", "points", "angles")}
        nodes = {"points": tuple(el["points"])} if "points" in el else {}
        if "angles" in el:
            nodes["angles"] = tuple(el["angles"])
        add = {"beam": m.add_beam, "truss": m.add_truss, "hinge": m.add_hinge}[kind]
        steps.append((f"[[model.elements]] #{i + 1} ({kind} '{el['name']}')", add, (el["name"],), {**nodes, **props}))
    steps += [(f"masses.{k}", m.add_mass, (k, v), {}) for k, v in table.get("masses", {}).items()]
    steps += [(f"inertias.{k}", m.add_inertia, (k, v), {}) for k, v in table.get("inertias", {}).items()]
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
        steps.append((f"[[model.outputs]] #{i + 1} ('{out['name']}')", m.add_midpoint_deflection,
                      (out["name"], tuple(out["ends"]), out["mid"], out["reference_length"]), {}))
    for where, add, args, kwargs in steps:
        try:
            add(*args, **kwargs)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
    return m


def check_element_form(check: Checker, model: dict) -> dict:
    """Structure and types of an element-model [model] table (names are checked when built)."""
    check.keys(model, "[model]", MODEL_FORM_KEYS, ("points", "elements"))
    out = {"name": check.string(model.get("name", "model"), "[model] name")}
    nonnegative = functools.partial(check.number, nonnegative=True)
    tables = {"points": functools.partial(_vector, check), "angles": check.number, "masses": nonnegative,
              "inertias": nonnegative, "forces": functools.partial(_vector, check), "torques": check.number,
              "prescribed": functools.partial(_function, check)}
    for key, check_value in tables.items():
        if key in model:
            table = check.table(model[key], f"[model.{key}]")
            out[key] = {k: check_value(v, f"[model.{key}] {k}") for k, v in table.items()}
    if "gravity" in model:
        out["gravity"] = _vector(check, model["gravity"], "[model] gravity")
    for key in ("fixed", "dynamic"):
        if key in model:
            out[key] = _names(check, model[key], f"[model] {key}")
    if "loads" in model:
        loads = model["loads"]
        if not isinstance(loads, list) or not all(isinstance(e, dict) for e in loads):
            check.fail("[[model.loads]]", f"must be an array of tables ([[model.loads]] sections), got {kind(loads)}")
        out["loads"] = [_load(check, entry, f"[[model.loads]] #{i + 1}") for i, entry in enumerate(loads)]
    for key, kinds in (("elements", _ELEMENT_KEYS), ("outputs", _OUTPUT_KEYS)):
        entries = model.get(key, [])
        if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
            check.fail(f"[[model.{key}]]",
                       f"must be an array of tables ([[model.{key}]] sections), got {kind(entries)}")
        out[key] = [_check_entry(check, entry, f"[[model.{key}]] #{i + 1}", kinds) for i, entry in enumerate(entries)]
    return out


def _check_entry(check: Checker, entry: dict, where: str, kinds: dict) -> dict:
    """One [[model.elements]] / [[model.outputs]] entry; ``type`` defaults to the only kind."""
    if "type" not in entry and len(kinds) > 1:
        check.fail(where, f"missing required key 'type' (one of: {', '.join(kinds)})")
    kind = check.string(entry.get("type", next(iter(kinds))), f"{where} type")
    if kind not in kinds:
        near = difflib.get_close_matches(kind, kinds, n=1, cutoff=0.6)
        check.fail(f"{where} type", f"unknown type '{kind}'; " + (f"did you mean '{near[0]}'? " if near else "")
                   + f"choose one of: {', '.join(kinds)}")
    required, optional = kinds[kind]
    check.keys(entry, where, ("type", *required, *optional), required)
    clean = {"type": kind, "name": check.string(entry["name"], f"{where} name")}
    for k in ("points", "angles", "ends"):
        if k in entry:
            clean[k] = _names(check, entry[k], f"{where} {k}", 2)
    if "mid" in entry:
        clean["mid"] = check.string(entry["mid"], f"{where} mid")
    for k in ("EA", "EI", "mass_per_length", "kelvin_voigt", "stiffness", "damping"):
        if k in entry:
            clean[k] = check.number(entry[k], f"{where} {k}", nonnegative=True)
    if "reference_length" in entry:
        clean["reference_length"] = check.number(entry["reference_length"], f"{where} reference_length", positive=True)
    for k in ("mode", "modes"):
        if k in entry:
            clean[k] = _modes(check, entry[k], f"{where} {k}", allow_many=k == "modes")
    return clean


def _vector(check: Checker, value, where: str) -> list[float]:
    if not isinstance(value, list) or len(value) != 2:
        check.fail(where, f"must be a pair [x, y] of numbers, got {kind(value)}")
    return [check.number(x, f"{where}[{i}]") for i, x in enumerate(value)]


def _names(check: Checker, value, where: str, count: int | None = None) -> list[str]:
    if not isinstance(value, list) or (count is not None and len(value) != count):
        what = f"a list of {count} names" if count else "a list of names"
        check.fail(where, f"must be {what}, got {kind(value)}")
    return [check.string(v, f"{where}[{i}]") for i, v in enumerate(value)]


def _modes(check: Checker, value, where: str, allow_many: bool):
    """Mode status: a string, or for beams also a list or a table by mode name."""
    if isinstance(value, str):
        return value
    if allow_many and isinstance(value, list):
        return [check.string(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if allow_many and isinstance(value, dict):
        return {k: check.string(v, f"{where}.{k}") for k, v in value.items()}
    check.fail(where, "must be a mode status such as \"rigid\", \"flexible\" or \"free\""
               + (" (or a list / table of them per mode)" if allow_many else "") + f", got {kind(value)}")



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


def _load(check: Checker, entry: dict, where: str) -> dict:
    """One [[model.loads]] entry: coordinate, or point and direction, and a function table."""
    if ("coordinate" in entry) == ("point" in entry):
        check.fail(where, "give either coordinate = \"<point>.x\" (or an angle) or point = \"<point>\" with a "
                          "direction")
    if "point" in entry and "direction" not in entry:
        check.fail(where, "a load on a point needs direction = [x, y]")
    out = _function(check, entry, where, keys=_LOAD_KEYS)
    if not any(k in entry for k in ("mean", "cosines", "sines", "samples")):
        check.fail(where, "give the load's samples = [...] over one turn or its Fourier coefficients")
    for k in ("coordinate", "point"):
        if k in entry:
            out[k] = check.string(entry[k], f"{where} {k}")
    if "direction" in entry:
        out["direction"] = _vector(check, entry["direction"], f"{where} direction")
    return out
