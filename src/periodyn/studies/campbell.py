"""Campbell studies: study files with a ``[campbell]`` table, the eigenvalues of a rotor
over spin speeds in the stationary frame (:func:`periodyn.rotor.campbell`).

Format (``description`` as in :mod:`periodyn.studies.spec`; the model is a rotor example,
``[model] example = "rotor"``, a rotor file, ``[model] rotor = "rotors/table1.toml"``
relative to the study file, see :mod:`periodyn.rotor.files`, or a spatial element model of a
spinning shaft with ``stations``, see :mod:`periodyn.studies.elements`)::

    [campbell]
    speeds = { start = 0.0, stop = 8000.0, num = 401, unit = "rpm" }   # unit: rad/s, rpm or Hz
    # or     { values = [4000.0], unit = "rpm" }
    modes = 8                # optional: the lowest modes by frequency (default all)
    frame = "auto"           # optional: auto | rotating | stationary
    eigensolver = "auto"     # optional: auto | dense | subset

    [campbell.grid]          # optional: a grid over builder parameters
    elements = [5, 20, 80]

    [[campbell.unbalance]]   # optional, without a grid: unbalance response (Bode) over the speeds
    station = 4              # station index
    mass = 0.01              # kg
    eccentricity = 0.01      # m
    phase = 0.0              # optional, rad

Results: one netCDF file, the Campbell dataset (dims: grid parameters, ``speed``,
``mode``) with ``threshold_speed`` (rad/s, per grid point) as a variable; with
``[[campbell.unbalance]]`` its group ``unbalance`` holds the synchronous response
(:func:`periodyn.rotor.response.unbalance_response`) with attribute ``critical_speeds``
(rad/s), read by :func:`unbalance_result`.
"""

from __future__ import annotations

import itertools
import json
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from . import cache
from .checks import FIXED_UNITS, Checker, FileSpec, parameter_check
from ..errors import InputError

__all__ = ["CampbellSpec", "parse_campbell", "run_campbell", "unbalance_result", "campbell_summary"]

_KEYS = ("speeds", "modes", "frame", "eigensolver", "grid", "unbalance")
_UNBALANCE = ("station", "mass", "eccentricity", "phase")
_FRAMES = ("auto", "rotating", "stationary")
_EIGENSOLVERS = ("auto", "dense", "subset")


@dataclass(frozen=True)
class CampbellSpec(FileSpec):
    """A validated Campbell study: speeds {start, stop, num} or {values} in ``speed_unit``,
    modes (None: all), frame, eigensolver, grid {builder parameter: values}, rotor file
    path (None for an example), unbalances ({station, mass, eccentricity, phase} each)."""

    speeds: dict
    speed_unit: str
    modes: int | None
    frame: str
    eigensolver: str
    grid: dict[str, list]
    rotor_file: str | None
    unbalance: tuple[dict, ...] = ()

    @property
    def kind(self) -> str:
        """"campbell"."""
        return "campbell"

    @property
    def inputs(self) -> dict:
        """The rotor file's document (a study of a rotor file is stale once it changes)."""
        return {} if self.rotor_file is None else {"rotor": tomllib.loads(Path(self.rotor_file).read_text())}

    def speed_values(self, omega=None) -> np.ndarray:
        """Spin speeds (k,) rad/s; ``omega`` (start, stop, num) in the file's unit replaces them."""
        if omega is not None:
            values = np.linspace(float(omega[0]), float(omega[1]), int(omega[2]))
        elif "values" in self.speeds:
            values = np.asarray(self.speeds["values"], float)
        else:
            values = np.linspace(self.speeds["start"], self.speeds["stop"], self.speeds["num"])
        return values * FIXED_UNITS[self.speed_unit]

    def build(self, **overrides):
        """The rotor from [model.parameters] (and ``overrides``); builder errors become
        InputError naming the file."""
        try:
            return self.builder(**{**self.parameters, **overrides})
        except (TypeError, ValueError, ArithmeticError, InputError) as exc:
            raise InputError(f"{self.source}: [model] {self.example} cannot be built from these parameters "
                             f"({type(exc).__name__}: {exc}); check [model.parameters] and [campbell.grid]") from None


def parse_campbell(check: Checker, table, *, source, name, text, description, example, builder, parameters,
                   accepted, settable, rotor_file=None) -> CampbellSpec:
    """Validate a [campbell] table (``check`` names the file)."""
    c = check.table(table, "[campbell]")
    check.keys(c, "[campbell]", _KEYS, ("speeds",))
    sp = check.table(c["speeds"], "[campbell] speeds")
    speed = lambda v, where: check.number(v, where, nonnegative=True)  # noqa: E731
    if "values" in sp:
        check.keys(sp, "[campbell] speeds", ("values", "unit"), ("values", "unit"))
        speeds = {"values": check.values(sp["values"], "[campbell] speeds.values", speed)}
    else:
        check.keys(sp, "[campbell] speeds", ("start", "stop", "num", "unit"), ("start", "stop", "num", "unit"))
        speeds = {"start": speed(sp["start"], "[campbell] speeds.start"),
                  "stop": speed(sp["stop"], "[campbell] speeds.stop"),
                  "num": check.integer(sp["num"], "[campbell] speeds.num", 1)}
    unit = check.string(sp["unit"], "[campbell] speeds.unit")
    if unit not in FIXED_UNITS:
        check.fail("[campbell] speeds.unit", f"unknown unit '{unit}'; use one of: {', '.join(FIXED_UNITS)}")
    modes = check.integer(c["modes"], "[campbell] modes", 1) if "modes" in c else None
    choices = {}
    for key, allowed in (("frame", _FRAMES), ("eigensolver", _EIGENSOLVERS)):
        choices[key] = check.string(c.get(key, "auto"), f"[campbell] {key}")
        if choices[key] not in allowed:
            check.fail(f"[campbell] {key}", f"unknown {key} '{choices[key]}'; choose one of: {', '.join(allowed)}")
    grid_table = check.table(c.get("grid", {}), "[campbell.grid]")
    check.keys(grid_table, f"[campbell.grid] (parameters of {example})", settable)
    grid = {k: check.values(v, f"[campbell.grid] {k}", parameter_check(check, accepted[k]))
            for k, v in grid_table.items()}
    entries = c.get("unbalance", [])
    if not isinstance(entries, list) or (entries and grid):
        check.fail("[[campbell.unbalance]]", "must be an array of tables [[campbell.unbalance]] in a study without "
                   "[campbell.grid] (the response is of one rotor)")
    unbalance = []
    for i, entry in enumerate(entries):
        where = f"[[campbell.unbalance]] number {i + 1}"
        check.keys(check.table(entry, where), where, _UNBALANCE, _UNBALANCE[:3])
        unbalance.append({"station": check.integer(entry["station"], f"{where} station", 0),
                          "mass": check.number(entry["mass"], f"{where} mass", nonnegative=True),
                          "eccentricity": check.number(entry["eccentricity"], f"{where} eccentricity",
                                                       nonnegative=True),
                          "phase": check.number(entry.get("phase", 0.0), f"{where} phase")})
    return CampbellSpec(source, name, text, description, example, builder, parameters, speeds, unit, modes,
                        choices["frame"], choices["eigensolver"], grid, rotor_file, tuple(unbalance))


def run_campbell(spec: CampbellSpec, out, *, omega=None, resume: bool = False, **_unused) -> xr.Dataset:
    """Compute the Campbell dataset of ``spec`` (every grid point) and write ``out`` ->
    Dataset; with ``resume`` a current ``out`` is read and one made otherwise refused."""
    from ..results import load, package_versions, save
    from ..rotor import campbell

    if cache.finished(out, spec, omega, resume):
        return load(out)
    speeds = spec.speed_values(omega)
    names = list(spec.grid)
    points, groups = [], {}
    for values in itertools.product(*spec.grid.values()):
        model = spec.build(**dict(zip(names, values)))
        ds = campbell(model, speeds, modes=spec.modes, frame=spec.frame, eigensolver=spec.eigensolver)
        if spec.unbalance:
            groups["unbalance"] = _unbalance(spec, model, speeds)
        threshold = ds.attrs.pop("threshold_speed")
        points.append(ds.assign(threshold_speed=((), threshold, {"units": "rad/s"})))
    ds = _stack(points, names, list(spec.grid.values()))
    ds.attrs.update({"model": spec.example, "description": spec.description, "speed_unit": spec.speed_unit,
                     "versions": json.dumps(package_versions()), **cache.stamp(spec, omega)})
    save(ds, out, groups=groups)
    return ds


def _unbalance(spec: CampbellSpec, model, speeds: np.ndarray) -> xr.Dataset:
    """The unbalance response of ``model`` over ``speeds`` with the damped critical speeds
    in that range as attribute ``critical_speeds`` (rad/s)."""
    from ..rotor.response import Unbalance, critical_speeds, unbalance_response

    try:
        response = unbalance_response(model, [Unbalance(**u) for u in spec.unbalance], speeds)
    except InputError as exc:
        raise InputError(f"{spec.source}: [[campbell.unbalance]]: {exc}") from None
    if np.ptp(speeds) > 0:
        response.attrs["critical_speeds"] = critical_speeds(model, (speeds.min(), speeds.max()))
    return response


def unbalance_result(path) -> xr.Dataset | None:
    """The unbalance response (group ``unbalance``) of a Campbell study's result file, or
    None when the study has no ``[[campbell.unbalance]]``."""
    from ..results import load_groups

    return load_groups(path)[1].get("unbalance")


def _stack(points: list[xr.Dataset], names: list[str], values: list[list]) -> xr.Dataset:
    """Datasets of a grid (row-major, last name fastest) stacked along one dimension per name."""
    if not names:
        return points[0]
    size = len(points) // len(values[0])
    rows = [_stack(points[i * size:(i + 1) * size], names[1:], values[1:]) for i in range(len(values[0]))]
    return xr.concat(rows, dim=xr.Variable(names[0], values[0]), combine_attrs="drop_conflicts")


def campbell_summary(ds: xr.Dataset, unbalance: xr.Dataset | None) -> str:
    """One line on a Campbell result: the stability threshold per grid point (rpm) and,
    with an ``unbalance`` response, its damped critical speeds (rpm)."""
    thresholds = np.atleast_1d(ds["threshold_speed"].values).ravel() * 30.0 / np.pi
    text = "stability threshold " + ", ".join(f"{t:.0f} rpm" if np.isfinite(t) else "none in range" for t in thresholds)
    if unbalance is None:
        return text
    critical = np.atleast_1d(unbalance.attrs.get("critical_speeds", [])) * 30.0 / np.pi
    return f"{text}, unbalance response with damped critical speeds " + (", ".join(f"{c:.0f} rpm" for c in critical)
                                                                         or "none")
