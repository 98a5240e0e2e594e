"""Value checks of an element model's ``[model]`` table (planar and spatial): each wrong
value fails through :class:`periodyn.studies.checks.Checker`, naming the file, the key and
the fix. Used by :mod:`periodyn.studies.elements`, which builds the model.

Spatial values (``[model] dimension = 3``, implied by ``[model.orientations]``):

- an orientation: ``{}`` (identity), ``{ axis = [x, y, z], angle = a }`` (rad), Euler
  parameters ``[l0, l1, l2, l3]`` or a rotation matrix ``[[...], [...], [...]]`` (body to
  global);
- a beam section (``[model.sections.<name>]`` or inline): the fields of
  :class:`periodyn.model.BeamSection` (EA, GJ, EI_y, EI_z, mass_per_length, polar_inertia,
  rotary_inertia_y, rotary_inertia_z; absent = 0) or a solid round section
  ``{ radius, youngs_modulus, poisson_ratio, density, rotary_inertia = true }``;
- a matrix of an independent element on k coordinates: k numbers (its diagonal) or k rows
  of k numbers.
"""

from __future__ import annotations

import numpy as np

from .checks import Checker, kind

__all__ = ["vector", "names", "modes", "orientation", "section", "matrix", "SECTION_FIELDS", "CIRCULAR_FIELDS"]

SECTION_FIELDS = ("EA", "GJ", "EI_y", "EI_z", "mass_per_length", "polar_inertia", "rotary_inertia_y",
                  "rotary_inertia_z")
CIRCULAR_FIELDS = ("radius", "youngs_modulus", "poisson_ratio", "density", "rotary_inertia")


def vector(check: Checker, value, where: str, size: int = 2) -> list[float]:
    """``size`` finite numbers ([x, y] or [x, y, z])."""
    if not isinstance(value, list) or len(value) != size:
        what = "a pair [x, y]" if size == 2 else "a triple [x, y, z]"
        check.fail(where, f"must be {what} of numbers, got {kind(value)}")
    return [check.number(x, f"{where}[{i}]") for i, x in enumerate(value)]


def names(check: Checker, value, where: str, count: int | None = None) -> list[str]:
    if not isinstance(value, list) or (count is not None and len(value) != count):
        what = f"a list of {count} names" if count else "a list of names"
        check.fail(where, f"must be {what}, got {kind(value)}")
    return [check.string(v, f"{where}[{i}]") for i, v in enumerate(value)]


def modes(check: Checker, value, where: str, allow_many: bool):
    """Mode status: a string, or for beams also a list or a table by mode name."""
    if isinstance(value, str):
        return value
    if allow_many and isinstance(value, list):
        return [check.string(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if allow_many and isinstance(value, dict):
        return {k: check.string(v, f"{where}.{k}") for k, v in value.items()}
    check.fail(where, "must be a mode status such as \"rigid\", \"flexible\" or \"free\""
               + (" (or a list / table of them per mode)" if allow_many else "") + f", got {kind(value)}")


def orientation(check: Checker, value, where: str):
    """A reference rotation (module docstring) as plain data: {} / {axis, angle} / a
    list of 4 numbers / 3 rows of 3."""
    if isinstance(value, dict):
        check.keys(value, where, ("axis", "angle"), ("axis", "angle") if value else ())
        if not value:
            return {}
        axis = vector(check, value["axis"], f"{where} axis", 3)
        if not np.linalg.norm(axis) > 0:
            check.fail(f"{where} axis", "is zero; give the direction of the rotation axis (any length but zero)")
        return {"axis": axis, "angle": check.number(value["angle"], f"{where} angle")}
    if isinstance(value, list) and len(value) == 3 and all(isinstance(r, list) for r in value):
        R = [vector(check, r, f"{where}[{i}]", 3) for i, r in enumerate(value)]
        a = np.array(R)
        if not (np.allclose(a @ a.T, np.eye(3), atol=1e-9) and np.linalg.det(a) > 0):
            check.fail(where, "is not a proper rotation matrix (orthonormal rows, determinant +1); give its "
                              "rows to 10 digits or use { axis = [x, y, z], angle = a }")
        return R
    if isinstance(value, list) and len(value) == 4:
        lam = [check.number(v, f"{where}[{i}]") for i, v in enumerate(value)]
        if not np.linalg.norm(lam) > 0:
            check.fail(where, "Euler parameters are all zero; give [cos(a/2), sin(a/2) n] for a rotation a about n")
        return lam
    check.fail(where, "must be {} (identity), { axis = [x, y, z], angle = a }, Euler parameters [l0, l1, l2, l3] "
                      f"or a rotation matrix (3 rows of 3), got {kind(value)}")


def section(check: Checker, value, where: str, sections: dict):
    """A beam section: the name of a [model.sections] entry, or a table (module docstring)."""
    if isinstance(value, str):
        if value not in sections:
            known = ", ".join(sections) or "none declared"
            check.fail(where, f"unknown section '{value}'; declare it in [model.sections.{value}] (known: {known})")
        return sections[value]
    table = check.table(value, where)
    if any(k in table for k in CIRCULAR_FIELDS):
        check.keys(table, f"{where} (a solid round section)", CIRCULAR_FIELDS, CIRCULAR_FIELDS[:4])
        out = {k: check.number(table[k], f"{where} {k}", positive=k != "poisson_ratio")
               for k in CIRCULAR_FIELDS[:4]}
        if not -1.0 < out["poisson_ratio"] < 0.5:
            check.fail(f"{where} poisson_ratio", f"must lie in (-1, 0.5), got {out['poisson_ratio']!r}")
        out["rotary_inertia"] = check.boolean(table.get("rotary_inertia", True), f"{where} rotary_inertia")
        return out
    check.keys(table, f"{where} (section data, or radius/youngs_modulus/poisson_ratio/density of a solid round "
                      "section)", SECTION_FIELDS)
    return {k: check.number(v, f"{where} {k}", nonnegative=True) for k, v in table.items()}


def matrix(check: Checker, value, where: str, size: int, *, symmetric_psd: bool = False) -> list[list[float]]:
    """A (size, size) matrix from k numbers (its diagonal) or k rows of k numbers; with
    symmetric_psd a mass matrix (symmetric, no negative eigenvalue)."""
    if isinstance(value, list) and len(value) == size and all(isinstance(v, list) for v in value):
        rows = [[check.number(x, f"{where}[{i}][{j}]") for j, x in enumerate(r)] for i, r in enumerate(value)]
        if any(len(r) != size for r in rows):
            check.fail(where, f"must have {size} rows of {size} numbers (one per coordinate), got rows of "
                              f"{sorted({len(r) for r in rows})}")
    elif isinstance(value, list) and len(value) == size:
        rows = np.diag([check.number(x, f"{where}[{i}]") for i, x in enumerate(value)]).tolist()
    else:
        check.fail(where, f"must be {size} numbers (the diagonal) or {size} rows of {size} numbers, one per "
                          f"coordinate, got {kind(value)}" + (f" of length {len(value)}" if isinstance(value, list)
                                                             else ""))
    if symmetric_psd:
        a = np.array(rows)
        if not np.allclose(a, a.T, rtol=1e-12, atol=0.0) or np.linalg.eigvalsh(0.5 * (a + a.T)).min() < \
                -1e-12 * np.abs(a).max():
            check.fail(where, "a mass matrix must be symmetric with no negative eigenvalue (kg); check its signs")
        if not np.abs(a).max() > 0:
            check.fail(where, "is zero; give the added mass (kg) or leave the key out")
    return rows
