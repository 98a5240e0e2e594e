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
        missing, unknown = required - set(entry), set(entry) - required - optional
        if missing or unknown:
            raise InputError(f"{path}: [[{key}]] number {i + 1} " + (f"lacks {sorted(missing)} " if missing else "")
                             + (f"has unknown keys {sorted(unknown)} " if unknown else "")
                             + f"(required {sorted(required)}, optional {sorted(optional)})")
    return entries


def load_rotor(path, *, elements: int | None = None) -> RotorModel:
    """The compiled rotor described by the TOML file ``path``; ``elements`` multiplies
    every shaft section's element count (mesh refinement)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"no rotor file at {path}")
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path} is not valid TOML: {exc}") from None
    unknown = set(data) - set(_TABLES) - set(_ARRAYS) - {"description"}
    if unknown:
        raise InputError(f"{path}: unknown tables {sorted(unknown)}; a rotor file has {sorted({*_TABLES, *_ARRAYS})}")
    for table, keys in _TABLES.items():
        extra = set(data.get(table, {})) - keys
        if extra:
            raise InputError(f"{path}: [{table}] has unknown keys {sorted(extra)}; allowed {sorted(keys)}")
    units = {"length": 1.0, "mass": 1.0, "force": 1.0, **data.get("units", {})}
    m, f, L = units["mass"], units["force"], units["length"]
    stiffness, damping, mass, inertia = f / L, f / L, f / L, f * L
    material = data.get("material", {})
    if set(material) != {"E", "density"}:
        raise InputError(f"{path}: [material] needs E and density")
    r = Rotor(str(data.get("rotor", {}).get("name", path.stem)))
    for s in _entries(data, "shaft", path):
        r.add_shaft(s["start"] * L, s["end"] * L, outer_diameter=s["outer_diameter"] * L,
                    inner_diameter=s.get("inner_diameter", 0.0) * L, E=material["E"] * f / L**2,
                    density=material["density"] * m / L**3, elements=s.get("elements", 1) * (elements or 1),
                    rotary_inertia=s.get("rotary_inertia", True), kelvin_voigt=s.get("kelvin_voigt", 0.0))
    for b in _entries(data, "bearing", path):
        coefficients = {k: v * (stiffness if k[0] == "k" else damping) for k, v in b.items() if k not in ("at", "to")}
        r.add_bearing(Bearing(b["at"] * L, **coefficients, to=b["to"] * L if "to" in b else None))
    for s in _entries(data, "seal", path):
        r.add_bearing(Seal(s["at"] * L, K=s["K"] * stiffness, k=s["k"] * stiffness, C=s["C"] * damping, c=s["c"] * damping))
    for d in _entries(data, "disk", path):
        r.add_disk(d["at"] * L, d["mass"] * mass, d["polar"] * inertia, d["diametral"] * inertia)
    for p in _entries(data, "mass", path):
        r.add_mass(p["at"] * L, p["mass"] * mass)
    return r.compile()
