"""Element models declared in a sweep file's ``[model]`` table: structure and type checks
(:func:`check_element_form`) and the model they build (:func:`element_model`), split in
powers of omega by :func:`periodyn.model.linearization.omega_split`."""

from __future__ import annotations

import difflib
import functools

from .checks import Checker, kind
from ..errors import ConvergenceError, InputError
from ..model.linearization import omega_split
from ..model import Model
from ..system import OmegaSplitModel

__all__ = ["element_model", "check_element_form", "MODEL_FORM_KEYS"]

_ELEMENT_KEYS = {
    "beam": (("name", "points", "angles"), ("modes", "EA", "EI", "mass_per_length", "kelvin_voigt")),
    "truss": (("name", "points"), ("mode", "EA", "mass_per_length", "kelvin_voigt")),
    "hinge": (("name", "angles"), ("mode", "stiffness", "damping")),
}
_OUTPUT_KEYS = {"midpoint_deflection": (("name", "ends", "mid", "reference_length"), ())}
MODEL_FORM_KEYS = ("name", "points", "angles", "elements", "masses", "inertias", "forces", "torques", "gravity",
                    "fixed", "prescribed", "dynamic", "outputs")


def element_model(table: dict, *, name: str = "model", samples: int = 64) -> OmegaSplitModel:
    """OmegaSplitModel of the element model in a validated ``[model]`` table (see the
    module docstring), sampled at ``samples`` crank angles; resamplable."""
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
    steps += [(f"prescribed.{k}", m.prescribe, (k, v), {}) for k, v in table.get("prescribed", {}).items()]
    steps += [(f"dynamic '{k}'", m.make_dynamic, (k,), {}) for k in table.get("dynamic", [])]
    for i, out in enumerate(table.get("outputs", [])):
        steps.append((f"[[model.outputs]] #{i + 1} ('{out['name']}')", m.add_midpoint_deflection,
                      (out["name"], tuple(out["ends"]), out["mid"], out["reference_length"]), {}))
    for where, add, args, kwargs in steps:
        try:
            add(*args, **kwargs)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
    try:
        compiled = m.compile()
        return omega_split(compiled, samples, name=name,
                           rebuild=functools.partial(element_model, table, name=name))
    except ConvergenceError as exc:  # e.g. the kinematics has no solution at some crank angle
        raise InputError(str(exc)) from None


def check_element_form(check: Checker, model: dict) -> dict:
    """Structure and types of an element-model [model] table (names are checked when built)."""
    check.keys(model, "[model]", MODEL_FORM_KEYS, ("points", "elements"))
    out = {"name": check.string(model.get("name", "model"), "[model] name")}
    nonnegative = functools.partial(check.number, nonnegative=True)
    tables = {"points": functools.partial(_vector, check), "angles": check.number, "masses": nonnegative,
              "inertias": nonnegative, "forces": functools.partial(_vector, check), "torques": check.number,
              "prescribed": check.number}
    for key, check_value in tables.items():
        if key in model:
            table = check.table(model[key], f"[model.{key}]")
            out[key] = {k: check_value(v, f"[model.{key}] {k}") for k, v in table.items()}
    if "gravity" in model:
        out["gravity"] = _vector(check, model["gravity"], "[model] gravity")
    for key in ("fixed", "dynamic"):
        if key in model:
            out[key] = _names(check, model[key], f"[model] {key}")
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

