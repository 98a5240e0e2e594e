"""Sweep files (TOML): schema, validation with clear messages, and the sweep they describe.

Format (every key except those marked optional is required)::

    description = "Schwab & Meijaard (2001), Fig. 3"     # optional

    [model]
    example = "pendulum"          # a builder in periodyn.examples

    [model.parameters]            # optional: keyword arguments of that builder
    zeta = 0.01

    [sweep]
    omega = { start = 0.01, stop = 1.4, num = 1400, unit = "omega0" }
    # or   { values = [0.1, 0.2], unit = "rad/s" }
    harmonics = 12
    samples = 64                  # optional: samples per period (default: the builder's)
    stability = true              # optional, default true
    method = "auto"               # optional: auto | sparse | dense | monodromy

    [sweep.grid]                  # optional: a grid over builder parameters
    zeta = [0.005, 0.01, 0.02]    # or { start = 0.005, stop = 0.02, num = 4 }

Instead of ``example``, ``[model]`` may declare an element model (see
:func:`element_model`): ``points``/``angles`` (nodes), ``[[model.elements]]`` of
``type`` beam/truss/hinge, ``masses``, ``inertias``, ``forces``, ``torques``, ``gravity``,
``fixed``, ``prescribed`` (name = rate), ``dynamic`` and ``[[model.outputs]]``; it is
built with :mod:`periodyn.model` and split in powers of omega by
:func:`periodyn.linearize.omega_split` (see ``sweeps/elliptic_pendulum_elements.toml``).

``unit`` is "rad/s", "rpm", "Hz", or a reference frequency of the model: a
``metadata`` entry named omega* of the model built from ``[model.parameters]``
(e.g. "omega0" for the pendulum). Every problem raises :class:`InputError` whose message
starts with the file name and the table, and says what to change.
"""

from __future__ import annotations

import difflib
import functools
import inspect
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from . import examples
from .errors import ConvergenceError, InputError
from .hill import METHODS
from .linearize import omega_split
from .model import Model
from .sweep import reference_frequencies
from .system import OmegaSplitModel

__all__ = ["SweepSpec", "SweepPlan", "load_sweep_file", "parse_sweep", "project_root", "known_examples",
           "element_model", "FIXED_UNITS"]

#: Speed units with a fixed factor to rad/s.
FIXED_UNITS = {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0, "Hz": 2.0 * math.pi}
_MAX_POINTS = 10_000_000
#: Harmonics a sweep file may ask for: the Hill matrix has (2m+1)·2n rows per speed.
MAX_HARMONICS = 1000


def project_root() -> Path:
    """The folder holding ``sweeps/``: the working directory if it has one, else the
    source checkout this package is installed from, else the working directory."""
    cwd = Path.cwd()
    if (cwd / "sweeps").is_dir():
        return cwd
    checkout = Path(__file__).resolve().parents[2]
    return checkout if (checkout / "sweeps").is_dir() else cwd


def known_examples() -> dict[str, Callable]:
    """Builders in periodyn.examples by name."""
    return {name: getattr(examples, name) for name in examples.__all__ if callable(getattr(examples, name))}


# ----------------------------------------------------------------------------- checks
class _Checker:
    """Raises InputError prefixed with the file and table."""

    def __init__(self, source: str):
        self.source = source

    def fail(self, where: str, message: str):
        raise InputError(f"{self.source}: {where}: {message}")

    def keys(self, table: dict, where: str, allowed: tuple[str, ...], required: tuple[str, ...] = ()) -> None:
        for key in table:
            if key not in allowed:
                near = difflib.get_close_matches(key, allowed, n=1, cutoff=0.6)
                hint = f"did you mean '{near[0]}'?" if near else f"valid keys: {', '.join(allowed)}"
                self.fail(where, f"unknown key '{key}'; {hint}")
        for key in required:
            if key not in table:
                self.fail(where, f"missing required key '{key}'")

    def table(self, value, where: str) -> dict:
        if not isinstance(value, dict):
            self.fail(where, f"must be a table ({{...}} or a [section]), got {_kind(value)}")
        return value

    def number(self, value, where: str, *, positive: bool = False, nonnegative: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(where, f"must be a number, got {_kind(value)}")
        if not math.isfinite(value):
            self.fail(where, f"must be finite, got {value!r}")
        if positive and value <= 0:
            self.fail(where, f"must be positive, got {value!r}")
        if nonnegative and value < 0:
            self.fail(where, f"must be >= 0, got {value!r}")
        return float(value)

    def integer(self, value, where: str, minimum: int | None = None) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            self.fail(where, f"must be an integer, got {_kind(value)}")
        if minimum is not None and value < minimum:
            self.fail(where, f"must be an integer >= {minimum}, got {value!r}")
        return value

    def boolean(self, value, where: str) -> bool:
        if not isinstance(value, bool):
            self.fail(where, f"must be true or false, got {_kind(value)}")
        return value

    def string(self, value, where: str) -> str:
        if not isinstance(value, str):
            self.fail(where, f"must be a string, got {_kind(value)}")
        return value

    def values(self, value, where: str, check: Callable[[Any, str], Any]) -> list:
        """A range {start, stop, num} or a non-empty list, each entry passed to ``check``."""
        if isinstance(value, dict):
            self.keys(value, where, ("start", "stop", "num"), ("start", "stop", "num"))
            start = check(value["start"], f"{where}.start")
            stop = check(value["stop"], f"{where}.stop")
            num = self.integer(value["num"], f"{where}.num", 1)
            if num > _MAX_POINTS:
                self.fail(f"{where}.num", f"{num} points is more than {_MAX_POINTS}; split the sweep")
            return [float(v) for v in np.linspace(start, stop, num)]
        if not isinstance(value, list) or not value:
            self.fail(where, f"must be a non-empty list of values or a range {{start, stop, num}}, got {_kind(value)}")
        return [check(v, f"{where}[{i}]") for i, v in enumerate(value)]


def _kind(value) -> str:
    """'an integer (3)', 'a table', ... for messages."""
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, list):
        return "a list"
    names = {bool: "a boolean", int: "an integer", float: "a number", str: "a string"}
    return f"{names.get(type(value), type(value).__name__)} ({value!r})"


# ----------------------------------------------------------------------------- builder parameters
def _parameter_check(check: _Checker, parameter: inspect.Parameter) -> Callable[[Any, str], Any]:
    """Type check for one builder keyword from its default value (or annotation)."""
    default = parameter.default
    annotation = str(parameter.annotation)
    if isinstance(default, bool) or annotation == "bool":
        return check.boolean
    if isinstance(default, int) or annotation == "int":
        return check.integer
    if isinstance(default, float) or annotation == "float":
        return check.number
    if isinstance(default, str) or annotation == "str":
        return check.string
    return lambda v, where: v


def _builder_parameters(builder: Callable) -> dict[str, inspect.Parameter]:
    return {name: p for name, p in inspect.signature(builder).parameters.items()
            if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)}


# ----------------------------------------------------------------------------- element models
_ELEMENT_KEYS = {
    "beam": (("name", "points", "angles"), ("modes", "EA", "EI", "mass_per_length", "kelvin_voigt")),
    "truss": (("name", "points"), ("mode", "EA", "mass_per_length", "kelvin_voigt")),
    "hinge": (("name", "angles"), ("mode", "stiffness", "damping")),
}
_OUTPUT_KEYS = {"midpoint_deflection": (("name", "ends", "mid", "reference_length"), ())}
_MODEL_FORM_KEYS = ("name", "points", "angles", "elements", "masses", "inertias", "forces", "torques", "gravity",
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


def _check_element_form(check: _Checker, model: dict) -> dict:
    """Structure and types of an element-model [model] table (names are checked when built)."""
    check.keys(model, "[model]", _MODEL_FORM_KEYS, ("points", "elements"))
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
                       f"must be an array of tables ([[model.{key}]] sections), got {_kind(entries)}")
        out[key] = [_check_entry(check, entry, f"[[model.{key}]] #{i + 1}", kinds) for i, entry in enumerate(entries)]
    return out


def _check_entry(check: _Checker, entry: dict, where: str, kinds: dict) -> dict:
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


def _vector(check: _Checker, value, where: str) -> list[float]:
    if not isinstance(value, list) or len(value) != 2:
        check.fail(where, f"must be a pair [x, y] of numbers, got {_kind(value)}")
    return [check.number(x, f"{where}[{i}]") for i, x in enumerate(value)]


def _names(check: _Checker, value, where: str, count: int | None = None) -> list[str]:
    if not isinstance(value, list) or (count is not None and len(value) != count):
        what = f"a list of {count} names" if count else "a list of names"
        check.fail(where, f"must be {what}, got {_kind(value)}")
    return [check.string(v, f"{where}[{i}]") for i, v in enumerate(value)]


def _modes(check: _Checker, value, where: str, allow_many: bool):
    """Mode status: a string, or for beams also a list or a table by mode name."""
    if isinstance(value, str):
        return value
    if allow_many and isinstance(value, list):
        return [check.string(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if allow_many and isinstance(value, dict):
        return {k: check.string(v, f"{where}.{k}") for k, v in value.items()}
    check.fail(where, "must be a mode status such as \"rigid\", \"flexible\" or \"free\""
               + (" (or a list / table of them per mode)" if allow_many else "") + f", got {_kind(value)}")


# ----------------------------------------------------------------------------- spec
@dataclass(frozen=True)
class SweepPlan:
    """What :func:`periodyn.sweep` gets: model (or builder with a grid), omega (k,) rad/s,
    parameter grid or None, reference frequency (name, rad/s) or None."""

    model: Any
    omega: np.ndarray
    parameters: dict[str, list] | None
    reference: tuple[str, float] | None


@dataclass(frozen=True)
class SweepSpec:
    """A validated sweep file. omega: {start, stop, num} or {values} in ``omega_unit``."""

    source: str
    name: str
    text: str
    description: str
    example: str
    builder: Callable = field(repr=False)
    parameters: dict[str, Any]
    omega: dict[str, Any]
    omega_unit: str
    harmonics: int
    samples: int | None
    stability: bool
    method: str
    grid: dict[str, list]

    def build(self, **overrides):
        """The model from [model.parameters] (and ``overrides``); builder errors become
        InputError naming the file."""
        kwargs = {**self.parameters, **overrides}
        if self.samples is not None and "samples" in _builder_parameters(self.builder):
            kwargs["samples"] = self.samples
        try:
            return self.builder(**kwargs)
        except InputError as exc:
            raise InputError(f"{self.source}: [model] {self.example}: {exc}") from None
        except (TypeError, ValueError, ArithmeticError) as exc:
            raise InputError(f"{self.source}: [model] {self.example} cannot be built from these parameters "
                             f"({type(exc).__name__}: {exc}); check [model.parameters]") from None

    def omega_scale(self, model) -> tuple[float, tuple[str, float] | None]:
        """(factor to rad/s, reference frequency for the results or None)."""
        refs = reference_frequencies(model)
        if self.omega_unit in FIXED_UNITS:
            return FIXED_UNITS[self.omega_unit], next(iter(refs.items()), None)
        if self.omega_unit not in refs:
            known = ", ".join([*FIXED_UNITS, *refs])
            raise InputError(f"{self.source}: [sweep] omega.unit: unknown unit '{self.omega_unit}'; "
                             f"use one of: {known}")
        return refs[self.omega_unit], (self.omega_unit, refs[self.omega_unit])

    def points(self, omega_range: tuple[float, float, int] | None = None) -> int:
        """Number of sweep points (speeds times grid points)."""
        return len(self.omega_values(omega_range)) * math.prod(len(v) for v in self.grid.values())

    def omega_values(self, omega_range: tuple[float, float, int] | None = None) -> np.ndarray:
        """Speeds in the file's unit; ``omega_range`` (start, stop, num) replaces the file's."""
        if omega_range is not None:
            start, stop, num = omega_range
            return np.linspace(float(start), float(stop), int(num))
        if "values" in self.omega:
            return np.asarray(self.omega["values"], dtype=float)
        return np.linspace(self.omega["start"], self.omega["stop"], self.omega["num"])

    def plan(self, omega_range: tuple[float, float, int] | None = None) -> SweepPlan:
        """Build the model and convert the speeds to rad/s."""
        model = self.build()
        samples = getattr(model, "samples", None)
        if self.samples is None and isinstance(samples, int) and samples < 2 * self.harmonics + 1:
            raise InputError(f"{self.source}: [sweep] harmonics: {self.harmonics} harmonics need at least "
                             f"{2 * self.harmonics + 1} samples per period but {self.example} samples {samples}; "
                             f"lower harmonics or add samples = {4 * self.harmonics + 1} to [sweep]")
        factor, reference = self.omega_scale(model)
        omega = self.omega_values(omega_range) * factor
        if self.grid:
            fixed = {**self.parameters}
            if self.samples is not None and "samples" in _builder_parameters(self.builder):
                fixed["samples"] = self.samples
            for name, values in self.grid.items():  # every grid point must build
                for value in (values[0], values[-1]):
                    self.build(**{name: value})
            return SweepPlan(functools.partial(self.builder, **fixed), omega, dict(self.grid), reference)
        return SweepPlan(model, omega, None, reference)


def parse_sweep(text: str, source: str = "<sweep file>", name: str = "sweep") -> SweepSpec:
    """Validate sweep-file text; raises InputError with the nearest fix."""
    check = _Checker(source)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source}: not valid TOML: {exc}") from None
    check.keys(data, "top level", ("description", "model", "sweep"), ("model", "sweep"))
    description = check.string(data.get("description", ""), "description")

    model = check.table(data["model"], "[model]")
    element_keys = [k for k in _MODEL_FORM_KEYS if k in model and k != "name"]
    if "example" in model and element_keys:
        check.fail("[model]", f"give either example = \"<name>\" or an element model ({', '.join(element_keys)}), "
                              "not both")
    if "example" in model or not element_keys:
        check.keys(model, "[model] (use example = \"<name>\" or declare points and [[model.elements]])",
                   ("example", "parameters"), ("example",))
        example = check.string(model["example"], "[model] example")
        builders = known_examples()
        if example not in builders:
            near = difflib.get_close_matches(example, builders, n=1, cutoff=0.6)
            hint = f"did you mean '{near[0]}'? " if near else ""
            check.fail("[model] example", f"unknown example '{example}'; {hint}known examples: {', '.join(builders)}")
        builder = builders[example]
        accepted = _builder_parameters(builder)
        settable = tuple(k for k in accepted if k != "samples")
    else:
        table = _check_element_form(check, model)
        example = table["name"] if "name" in model else name
        builder = functools.partial(element_model, table, name=example)
        accepted, settable = {"samples": None}, ()

    parameters = check.table(model.get("parameters", {}), "[model.parameters]")
    if "samples" in parameters:
        check.fail("[model.parameters]", "give samples in [sweep] (samples = ...), not as a model parameter")
    check.keys(parameters, f"[model.parameters] of {example}", settable)
    parameters = {k: _parameter_check(check, accepted[k])(v, f"[model.parameters] {k}") for k, v in parameters.items()}

    sweep = check.table(data["sweep"], "[sweep]")
    check.keys(sweep, "[sweep]", ("omega", "harmonics", "samples", "stability", "method", "grid"),
               ("omega", "harmonics"))
    omega = check.table(sweep["omega"], "[sweep] omega")
    if "unit" not in omega:
        check.fail("[sweep] omega", "missing unit; add unit = \"rad/s\" (or \"rpm\", \"Hz\", or a reference "
                                    "frequency of the model such as \"omega0\")")
    unit = check.string(omega["unit"], "[sweep] omega.unit")
    speed = functools.partial(check.number, positive=True)
    if "values" in omega:
        check.keys(omega, "[sweep] omega", ("values", "unit"))
        omega_spec = {"values": check.values(omega["values"], "[sweep] omega.values", speed)}
    else:
        check.keys(omega, "[sweep] omega", ("start", "stop", "num", "unit"), ("start", "stop", "num"))
        omega_spec = {"start": speed(omega["start"], "[sweep] omega.start"),
                      "stop": speed(omega["stop"], "[sweep] omega.stop"),
                      "num": check.integer(omega["num"], "[sweep] omega.num", 1)}
        if omega_spec["num"] > _MAX_POINTS:
            check.fail("[sweep] omega.num", f"{omega_spec['num']} speeds is more than {_MAX_POINTS}; split the sweep")
    harmonics = check.integer(sweep["harmonics"], "[sweep] harmonics", 1)
    if harmonics > MAX_HARMONICS:
        check.fail("[sweep] harmonics", f"{harmonics} harmonics is more than a sweep can hold (at most "
                                        f"{MAX_HARMONICS}); 10-40 resolve the papers' examples")
    samples = check.integer(sweep["samples"], "[sweep] samples", 1) if "samples" in sweep else None
    if samples is not None and samples < 2 * harmonics + 1:
        check.fail("[sweep] samples", f"{samples} samples cannot resolve {harmonics} harmonics; "
                                      f"use samples >= {2 * harmonics + 1} (>= {4 * harmonics + 1} recommended)")
    stability = check.boolean(sweep.get("stability", True), "[sweep] stability")
    method = check.string(sweep.get("method", "auto"), "[sweep] method")
    if method not in METHODS:
        near = difflib.get_close_matches(method, METHODS, n=1, cutoff=0.6)
        check.fail("[sweep] method", f"unknown method '{method}'; " + (f"did you mean '{near[0]}'? " if near else "")
                   + f"choose one of: {', '.join(METHODS)}")

    grid_table = check.table(sweep.get("grid", {}), "[sweep.grid]")
    if grid_table and not settable:
        check.fail("[sweep.grid]", f"'{example}' has no parameters to vary; a grid needs an example builder "
                                   "(example = \"<name>\") with keyword parameters")
    check.keys(grid_table, f"[sweep.grid] (parameters of {example})", settable)
    grid = {k: check.values(v, f"[sweep.grid] {k}", _parameter_check(check, accepted[k]))
            for k, v in grid_table.items()}
    points = math.prod(len(v) for v in grid.values()) * (omega_spec.get("num") or len(omega_spec.get("values", [])))
    if points > _MAX_POINTS:
        check.fail("[sweep.grid]", f"{points} points is more than {_MAX_POINTS}; split the sweep")
    return SweepSpec(source, name, text, description, example, builder, parameters, omega_spec, unit,
                     harmonics, samples, stability, method, grid)


def load_sweep_file(path) -> SweepSpec:
    """Read and validate ``path`` (a .toml sweep file)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        near = sorted(p.name for p in path.parent.glob("*.toml")) if path.parent.is_dir() else []
        hint = f"; files in {path.parent}: {', '.join(near)}" if near else ""
        raise InputError(f"no sweep file at {path}{hint}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read sweep file {path}: {exc}") from None
    return parse_sweep(text, str(path), path.stem)
