"""Tables of an element model's ``[model]`` beyond points, angles and elements: checks
(:func:`check_tables`) and the builder steps (:func:`node_steps`, :func:`part_steps`).

::

    [model.orientations]          # spatial: orientation nodes (values: periodyn.studies.element_values)
    R0 = {}                       # identity
    R1 = { axis = [0.0, 0.0, 1.0], angle = 0.5235987755982988 }

    [model.sections.shaft]        # spatial beam sections, named by spatial_beam's section = "shaft"
    radius = 0.03
    youngs_modulus = 210e9
    poisson_ratio = 0.3
    density = 7850.0

    [[model.rigid_bodies]]        # spatial: inertia (3 numbers, the diagonal, or 3 rows) kg m^2 in the
    orientation = "R4"            # node's frame about the centre of mass, optional point and mass (kg)
    inertia = [0.1, 0.05, 0.05]
    point = "P4"
    mass = 12.0

    [[model.independent]]         # eq. 11-12 on nodal coordinates: f = -K x - C x' - M x'' + force
    name = "bearing"
    coordinates = ["P0.y", "P0.z"]
    stiffness = [1e7, 1e7]        # k numbers (diagonal) or k rows; N/m (N m/rad)
    stiffness_omega = ...         # times omega (N s/m), stiffness_omega2 times omega^2
    damping = ...                 # N s/m, damping_omega times omega
    mass = ...                    # kg (symmetric, no negative eigenvalue)
    force = [0.0, 0.0]            # N, constant

    [model.frequencies]           # reference frequencies (rad/s) for [sweep] omega.unit
    omega_b = 767.9

    stations = ["P0", "P1"]       # [campbell] studies of a spatial rotor: points on the shaft
"""

from __future__ import annotations

import numpy as np

from .checks import Checker, kind
from .element_values import matrix, names, orientation, section, vector
from ..model import BeamSection, Model
from ..model.elements import IndependentElement
from ..model.spatial import axis_angle

__all__ = ["check_tables", "node_steps", "part_steps", "element_arguments", "beam_section", "rotation"]

_RIGID_BODY = (("orientation", "inertia"), ("point", "mass"))
_MATRICES = ("mass", "damping", "damping_omega", "stiffness", "stiffness_omega", "stiffness_omega2")
_INDEPENDENT = (("name", "coordinates"), (*_MATRICES, "force"))


def check_tables(check: Checker, model: dict, dim: int) -> dict:
    """The checked tables of the module docstring present in ``model``."""
    out = {}
    if "orientations" in model:
        table = check.table(model["orientations"], "[model.orientations]")
        out["orientations"] = {k: orientation(check, v, f"[model.orientations] {k}") for k, v in table.items()}
    if "sections" in model:
        table = check.table(model["sections"], "[model.sections]")
        out["sections"] = {k: section(check, check.table(v, f"[model.sections.{k}]"), f"[model.sections.{k}]", {})
                           for k, v in table.items()}
    for key, form, entry_check in (("rigid_bodies", _RIGID_BODY, _rigid_body),
                                   ("independent", _INDEPENDENT, _independent)):
        if key not in model:
            continue
        if dim == 2 and key == "rigid_bodies":
            check.fail("[[model.rigid_bodies]]", "is for spatial models; a planar model has [model.inertias] "
                                                 "(and [model.masses])")
        entries = model[key]
        if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
            check.fail(f"[[model.{key}]]", f"must be an array of tables ([[model.{key}]] sections), got "
                                           f"{kind(entries)}")
        out[key] = []
        for i, entry in enumerate(entries):
            where = f"[[model.{key}]] #{i + 1}"
            check.keys(entry, where, form[0] + form[1], form[0])
            out[key].append(entry_check(check, entry, where))
    if "frequencies" in model:
        table = check.table(model["frequencies"], "[model.frequencies]")
        for k in table:
            if not k.startswith("omega"):
                check.fail(f"[model.frequencies] {k}", "a reference frequency's name starts with 'omega' (e.g. "
                                                       "omega_b), so that [sweep] omega.unit can name it")
        out["frequencies"] = {k: check.number(v, f"[model.frequencies] {k}", positive=True) for k, v in table.items()}
    if "stations" in model:
        out["stations"] = names(check, model["stations"], "[model] stations")
        if not out["stations"]:
            check.fail("[model] stations", "is empty; name the points on the shaft axis")
    return out


def _rigid_body(check: Checker, entry: dict, where: str) -> dict:
    out = {"orientation": check.string(entry["orientation"], f"{where} orientation")}
    inertia = entry["inertia"]
    if isinstance(inertia, list) and len(inertia) == 3 and not any(isinstance(v, list) for v in inertia):
        out["inertia"] = np.diag(vector(check, inertia, f"{where} inertia", 3)).tolist()
    else:
        out["inertia"] = matrix(check, inertia, f"{where} inertia", 3)
    if ("point" in entry) != ("mass" in entry):
        check.fail(where, "give both point = \"<centre of mass>\" and mass = <kg>, or neither (a rotational "
                          "inertia only)")
    if "point" in entry:
        out["point"] = check.string(entry["point"], f"{where} point")
        out["mass"] = check.number(entry["mass"], f"{where} mass", positive=True)
    return out


def _independent(check: Checker, entry: dict, where: str) -> dict:
    out = {"name": check.string(entry["name"], f"{where} name"),
           "coordinates": names(check, entry["coordinates"], f"{where} coordinates")}
    k = len(out["coordinates"])
    if k == 0 or len(set(out["coordinates"])) < k:
        check.fail(f"{where} coordinates", "must name one or more different nodal coordinates ('<point>.y', ...)")
    if not any(key in entry for key in (*_MATRICES, "force")):
        check.fail(where, f"give at least one of {', '.join(_MATRICES)}, force")
    for key in _MATRICES:
        if key in entry:
            out[key] = matrix(check, entry[key], f"{where} {key}", k, symmetric_psd=key == "mass")
    if "force" in entry:
        out["force"] = vector(check, entry["force"], f"{where} force", k)
    return out


def rotation(value):
    """A checked orientation value as the argument of Model.add_orientation."""
    if isinstance(value, dict):
        return axis_angle(value["axis"], value["angle"]) if value else None
    return np.array(value, dtype=float)


def beam_section(data: dict) -> BeamSection:
    """A checked section table as a BeamSection."""
    if "radius" in data:
        return BeamSection.solid_circular(data["radius"], data["youngs_modulus"], data["poisson_ratio"],
                                          data["density"], rotary_inertia=data.get("rotary_inertia", True))
    return BeamSection(**data)


def element_arguments(kwargs: dict) -> dict:
    """Builder arguments of a checked element entry that change form: section, rotation,
    per-mode Kelvin-Voigt constants."""
    out = {}
    if "section" in kwargs:
        out["section"] = beam_section(kwargs["section"])
    if "rotation" in kwargs:
        out["rotation"] = rotation(kwargs["rotation"])
    if isinstance(kwargs.get("kelvin_voigt"), list):
        out["kelvin_voigt"] = tuple(kwargs["kelvin_voigt"])
    return out


def node_steps(m: Model, table: dict) -> list:
    """Steps (where, method, args, kwargs) adding the orientation nodes."""
    return [(f"orientation '{k}'", m.add_orientation, (k, rotation(v)), {})
            for k, v in table.get("orientations", {}).items()]


def part_steps(m: Model, table: dict) -> list:
    """Steps adding the rigid bodies and the independent elements."""
    steps = [(f"[[model.rigid_bodies]] #{i + 1} ('{b['orientation']}')", m.add_rigid_body,
              (b["orientation"], b["inertia"]), {k: b[k] for k in ("point", "mass") if k in b})
             for i, b in enumerate(table.get("rigid_bodies", []))]
    for i, e in enumerate(table.get("independent", [])):
        steps.append((f"[[model.independent]] #{i + 1} ('{e['name']}')", m.add_independent,
                      (_independent_element(e),), {}))
    return steps


def _independent_element(e: dict) -> IndependentElement:
    """The IndependentElement of a checked entry: omega powers up to the highest given."""
    k = len(e["coordinates"])

    def powers(keys):
        given = [np.array(e[key], dtype=float) if key in e else None for key in keys]
        top = max((i for i, g in enumerate(given) if g is not None), default=-1)
        return tuple(np.zeros((k, k)) if g is None else g for g in given[:top + 1])

    return IndependentElement(e["name"], tuple(e["coordinates"]),
                              stiffness=powers(("stiffness", "stiffness_omega", "stiffness_omega2")),
                              damping=powers(("damping", "damping_omega")),
                              mass=np.array(e["mass"], dtype=float) if "mass" in e else None,
                              force=np.array(e["force"], dtype=float) if "force" in e else None)
