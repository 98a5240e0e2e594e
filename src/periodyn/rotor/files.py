"""Rotor files (TOML): shaft sections, material, disks, bearings, seals and masses.

Layout (values in SI unless a ``[units]`` table gives factors to SI for length, mass
and force; derived quantities follow: E in force/length^2, density mass/length^3,
stiffness force/length, damping force s/length, disk and point masses force s^2/length,
moments of inertia force s^2 length)::

    [rotor]     name = "..."
    [units]     length = 0.0254, mass = 0.45359237, force = 4.4482216   (optional)
    [material]  E = ..., density = ...
    [[shaft]]   start, end, outer_diameter, elements = 1, inner_diameter = 0, rotary_inertia = true,
                kelvin_voigt = 0 (s)
    [[bearing]] at, kyy, kzz, kyz = 0, kzy = 0, cyy = 0, czz = 0, cyz = 0, czy = 0, to (station)
    [[seal]]    at, K, k, C, c
    [[disk]]    at, mass, polar, diametral
    [[mass]]    at, mass
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

from ..errors import InputError
from .elements import Bearing, Seal
from .model import Rotor, RotorModel

__all__ = ["load_rotor"]

_TABLES = {"rotor": {"name"}, "units": {"length", "mass", "force"}, "material": {"E", "density"}}
_ARRAYS = {
    "shaft": ({"start", "end", "outer_diameter"}, {"elements", "inner_diameter", "rotary_inertia", "kelvin_voigt"}),
    "bearing": ({"at", "kyy", "kzz"}, {"kyz", "kzy", "cyy", "czz", "cyz", "czy", "to"}),
    "seal": ({"at", "K", "k", "C", "c"}, set()),
    "disk": ({"at", "mass", "polar", "diametral"}, set()),
    "mass": ({"at", "mass"}, set()),
}


def _entries(data: dict, key: str, path: Path) -> list[dict]:
    required, optional = _ARRAYS[key]
    entries = data.get(key, [])
    if not isinstance(entries, list):
        raise InputError(f"{path}: '{key}' must be an array of tables, written [[{key}]]")
    for i, entry in enumerate(entries):
        if not isinstance(entry, dict):
            raise InputError(f"{path}: [[{key}]] number {i + 1} must be a table of keys, got {entry!r}")
        missing, unknown = required - set(entry), set(entry) - required - optional
        if missing or unknown:
            raise InputError(f"{path}: [[{key}]] number {i + 1} " + (f"lacks {sorted(missing)} " if missing else "")
                             + (f"has unknown keys {sorted(unknown)} " if unknown else "")
                             + f"(required {sorted(required)}, optional {sorted(optional)})")
    return entries


def _number(path: Path, where: str, key: str, value, positive: bool = False) -> float:
    """A finite number from the file (an int or a float, not a bool or a string)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or (positive and value <= 0):
        rule = "a positive finite number" if positive else "a finite number"
        raise InputError(f"{path}: {where} {key} must be {rule} (in the file's units), got {value!r}")
    return float(value)


def _checked(path: Path, where: str, entry: dict) -> dict:
    """``entry`` with its values type-checked: elements a positive integer, rotary_inertia
    true/false, every other value a finite number."""
    for key, value in entry.items():
        if key == "elements":
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise InputError(f"{path}: {where} elements must be a positive integer, got {value!r}")
        elif key == "rotary_inertia":
            if not isinstance(value, bool):
                raise InputError(f"{path}: {where} rotary_inertia must be true or false, got {value!r}")
        else:
            _number(path, where, key, value)
    return entry


def _read(path: Path) -> dict:
    if not path.is_file():
        raise InputError(f"no rotor file at {path}")
    try:
        return tomllib.loads(path.read_bytes().decode("utf-8"))
    except UnicodeDecodeError:
        raise InputError(f"{path} is not a text file (not UTF-8); a rotor file is TOML text") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path} is not valid TOML: {exc}") from None
    except OSError as exc:
        raise InputError(f"cannot read the rotor file {path}: {exc.strerror or exc}") from None


def load_rotor(path, *, elements: int | None = None) -> RotorModel:
    """The compiled rotor described by the TOML file ``path``; ``elements`` multiplies
    every shaft section's element count (mesh refinement)."""
    path = Path(path)
    data = _read(path)
    unknown = set(data) - set(_TABLES) - set(_ARRAYS) - {"description"}
    if unknown:
        raise InputError(f"{path}: unknown tables {sorted(unknown)}; a rotor file has {sorted({*_TABLES, *_ARRAYS})}")
    for table, keys in _TABLES.items():
        if not isinstance(data.get(table, {}), dict):
            raise InputError(f"{path}: [{table}] must be a table, written [{table}]")
        extra = set(data.get(table, {})) - keys
        if extra:
            raise InputError(f"{path}: [{table}] has unknown keys {sorted(extra)}; allowed {sorted(keys)}")
    units = {"length": 1.0, "mass": 1.0, "force": 1.0, **data.get("units", {})}
    m, f, L = (_number(path, "[units]", key, units[key], positive=True) for key in ("mass", "force", "length"))
    stiffness, damping, mass, inertia = f / L, f / L, f / L, f * L
    material = data.get("material", {})
    if set(material) != {"E", "density"}:
        raise InputError(f"{path}: [material] needs E and density")
    E, density = (_number(path, "[material]", key, material[key], positive=True) for key in ("E", "density"))
    name = data.get("rotor", {}).get("name", path.stem)
    if not isinstance(name, str):
        raise InputError(f"{path}: [rotor] name must be a string, got {name!r}")
    r = Rotor(name, length_unit=L)
    tables = {key: [(f"[[{key}]] number {i + 1}", _checked(path, f"[[{key}]] number {i + 1}", entry))
                    for i, entry in enumerate(_entries(data, key, path))] for key in _ARRAYS}

    def add(where: str, build) -> None:
        try:
            build()
        except InputError as exc:
            raise InputError(f"{path}: {where}: {exc}") from None

    for where, s in tables["shaft"]:
        add(where, lambda s=s: r.add_shaft(
            s["start"] * L, s["end"] * L, outer_diameter=s["outer_diameter"] * L,
            inner_diameter=s.get("inner_diameter", 0.0) * L, E=E * f / L**2, density=density * m / L**3,
            elements=s.get("elements", 1) * (elements or 1), rotary_inertia=s.get("rotary_inertia", True),
            kelvin_voigt=s.get("kelvin_voigt", 0.0)))
    for where, b in tables["bearing"]:
        coefficients = {k: v * (stiffness if k[0] == "k" else damping) for k, v in b.items() if k not in ("at", "to")}
        add(where, lambda b=b, c=coefficients: r.add_bearing(Bearing(b["at"] * L, **c,
                                                                     to=b["to"] * L if "to" in b else None)))
    for where, s in tables["seal"]:
        add(where, lambda s=s: r.add_bearing(Seal(s["at"] * L, K=s["K"] * stiffness, k=s["k"] * stiffness,
                                                  C=s["C"] * damping, c=s["c"] * damping)))
    for where, d in tables["disk"]:
        add(where, lambda d=d: r.add_disk(d["at"] * L, d["mass"] * mass, d["polar"] * inertia,
                                          d["diametral"] * inertia))
    for where, p in tables["mass"]:
        add(where, lambda p=p: r.add_mass(p["at"] * L, p["mass"] * mass))
    try:
        return r.compile()
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
