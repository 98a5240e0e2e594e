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
    stability = true              # optional: true (= "auto"), false, or a stability method:
                                  # auto | hill | sparse | dense | monodromy | magnus
    output_units = { phi = "rad" }  # optional: unit of each output in the results

    [sweep.grid]                  # optional: a grid over builder parameters
    zeta = [0.005, 0.01, 0.02]    # or { start = 0.005, stop = 0.02, num = 4 }

Instead of ``example``, ``[model]`` may declare an element model (see
:func:`element_model`): ``points``/``angles`` (nodes), ``[[model.elements]]`` of
``type`` beam/truss/hinge, ``masses``, ``inertias``, ``forces``, ``torques``, ``gravity``,
``fixed``, ``prescribed`` (name = rate), ``dynamic`` and ``[[model.outputs]]``; it is
built with :mod:`periodyn.model` and split in powers of omega by
:func:`periodyn.model.linearization.omega_split` (see ``sweeps/elliptic_pendulum_elements.toml``).

A file with a ``[continuation]`` table instead of ``[sweep]`` is a continuation study of a
DAE example (schema and runner in :mod:`periodyn.studies.continuation`), one with a ``[transient]`` table
the motion from rest at one speed (:mod:`periodyn.studies.transient`); :func:`parse_sweep`
gives a :class:`SweepSpec`, a :class:`~periodyn.studies.continuation.StudySpec` or a
:class:`~periodyn.studies.transient.TransientSpec`, ``spec.kind`` says which.

``unit`` is "rad/s", "rpm", "Hz", or a reference frequency of the model: a
``metadata`` entry named omega* of the model built from ``[model.parameters]``
(e.g. "omega0" for the pendulum). Every problem raises :class:`InputError` whose message
starts with the file name and the table, and says what to change.
"""

from __future__ import annotations

import difflib
import functools
import warnings
import inspect
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .. import examples
from .checks import FIXED_UNITS, MAX_POINTS, Checker, FileSpec
from .elements import MODEL_FORM_KEYS, check_element_form, element_model
from ..engine.job import reference_frequencies
from ..errors import InputError
from ..stability.methods import names
from ..results import load_if_made_from
from .continuation import StudySpec, ensure_study, parse_continuation
from ..engine.front import sweep_file
from .transient import TransientSpec, ensure_transient, parse_transient

__all__ = ["SweepSpec", "StudySpec", "TransientSpec", "SweepPlan", "load_sweep_file", "parse_sweep", "project_root", "known_examples",
           "element_model", "ensure", "FIXED_UNITS", "MAX_HARMONICS"]

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


# ----------------------------------------------------------------------------- builder parameters
def _parameter_check(check: Checker, parameter: inspect.Parameter) -> Callable[[Any, str], Any]:
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
class SweepSpec(FileSpec):
    """A validated sweep file. omega: {start, stop, num} or {values} in ``omega_unit``;
    output_units: {output: unit} for the results (empty: the model's)."""

    omega: dict[str, Any]
    omega_unit: str
    harmonics: int
    samples: int | None
    stability: bool
    method: str
    grid: dict[str, list]
    output_units: dict[str, str] = field(default_factory=dict)

    @property
    def kind(self) -> str:
        """"sweep" (a StudySpec says "continuation")."""
        return "sweep"

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


def _model(check: Checker, data: dict, name: str) -> tuple:
    """(example, builder, accepted parameters, settable names, parameters) of [model]."""
    model = check.table(data["model"], "[model]")
    element_keys = [k for k in MODEL_FORM_KEYS if k in model and k != "name"]
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
        table = check_element_form(check, model)
        example = table["name"] if "name" in model else name
        builder = functools.partial(element_model, table, name=example)
        accepted, settable = {"samples": None}, ()

    parameters = check.table(model.get("parameters", {}), "[model.parameters]")
    if "samples" in parameters:
        check.fail("[model.parameters]", "give samples in [sweep] (samples = ...), not as a model parameter")
    check.keys(parameters, f"[model.parameters] of {example}", settable)
    parameters = {k: _parameter_check(check, accepted[k])(v, f"[model.parameters] {k}") for k, v in parameters.items()}
    return example, builder, accepted, settable, parameters


def parse_sweep(text: str, source: str = "<sweep file>", name: str = "sweep") -> SweepSpec | StudySpec | TransientSpec:
    """Validate sweep-file text -> SweepSpec (a [sweep] file), StudySpec (a [continuation]
    file) or TransientSpec (a [transient] file; ``spec.kind`` tells which); raises
    InputError with the nearest fix."""
    check = Checker(source)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source}: not valid TOML: {exc}") from None
    kinds = ("sweep", "continuation", "transient")
    check.keys(data, "top level", ("description", "model") + kinds, ("model",))
    given = [k for k in kinds if k in data]
    if not given:
        check.fail("top level", "missing required key 'sweep' (a speed sweep), 'continuation' (a continuation "
                                "study of a DAE example) or 'transient' (the motion from rest at one speed)")
    if len(given) > 1:
        check.fail("top level", f"give one of [sweep] (a speed sweep), [continuation] (a study) or [transient], "
                                f"not {' and '.join(f'[{k}]' for k in given)}")
    description = check.string(data.get("description", ""), "description")
    example, builder, accepted, settable, parameters = _model(check, data, name)
    if given[0] != "sweep":
        parse = parse_continuation if given[0] == "continuation" else parse_transient
        return parse(check, data[given[0]], source=source, name=name, text=text, description=description,
                     example=example, builder=builder, parameters=parameters)

    sweep = check.table(data["sweep"], "[sweep]")
    check.keys(sweep, "[sweep]", ("omega", "harmonics", "samples", "stability", "method", "grid", "output_units"),
               ("omega", "harmonics"))
    units = check.table(sweep.get("output_units", {}), "[sweep] output_units")
    output_units = {k: check.string(v, f"[sweep] output_units.{k}") for k, v in units.items()}
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
        if omega_spec["num"] > MAX_POINTS:
            check.fail("[sweep] omega.num", f"{omega_spec['num']} speeds is more than {MAX_POINTS}; split the sweep")
    harmonics = check.integer(sweep["harmonics"], "[sweep] harmonics", 1)
    if harmonics > MAX_HARMONICS:
        check.fail("[sweep] harmonics", f"{harmonics} harmonics is more than a sweep can hold (at most "
                                        f"{MAX_HARMONICS}); 10-40 resolve the papers' examples")
    samples = check.integer(sweep["samples"], "[sweep] samples", 1) if "samples" in sweep else None
    if samples is not None and samples < 2 * harmonics + 1:
        check.fail("[sweep] samples", f"{samples} samples cannot resolve {harmonics} harmonics; "
                                      f"use samples >= {2 * harmonics + 1} (>= {4 * harmonics + 1} recommended)")
    stability, method = _stability(check, sweep)

    grid_table = check.table(sweep.get("grid", {}), "[sweep.grid]")
    if grid_table and not settable:
        check.fail("[sweep.grid]", f"'{example}' has no parameters to vary; a grid needs an example builder "
                                   "(example = \"<name>\") with keyword parameters")
    check.keys(grid_table, f"[sweep.grid] (parameters of {example})", settable)
    grid = {k: check.values(v, f"[sweep.grid] {k}", _parameter_check(check, accepted[k]))
            for k, v in grid_table.items()}
    points = math.prod(len(v) for v in grid.values()) * (omega_spec.get("num") or len(omega_spec.get("values", [])))
    if points > MAX_POINTS:
        check.fail("[sweep.grid]", f"{points} points is more than {MAX_POINTS}; split the sweep")
    return SweepSpec(source, name, text, description, example, builder, parameters, omega_spec, unit,
                     harmonics, samples, stability, method, grid, output_units)


def _stability(check: Checker, sweep: dict) -> tuple[bool, str]:
    """(stability on, method) from ``stability = true | false | "<method>"`` and the old
    ``method = "<method>"`` key (still read, with a DeprecationWarning)."""
    stability = sweep.get("stability", True)
    if isinstance(stability, str):
        _known_method(check, stability, "[sweep] stability", "must be true or false or a stability method, ")
        if "method" in sweep:
            check.fail("[sweep] method", f"give the stability method once: stability = \"{stability}\" (method is "
                                         "its old name)")
        return True, stability
    stability = check.boolean(stability, "[sweep] stability")
    if "method" not in sweep:
        return stability, "auto"
    method = _known_method(check, check.string(sweep["method"], "[sweep] method"), "[sweep] method")
    warnings.warn(f"{check.source}: [sweep] method = \"{method}\" is the old name of stability = \"{method}\" "
                  "(stability = false keeps it off); the old key goes in the next release", DeprecationWarning,
                  stacklevel=3)
    return stability, method


def _known_method(check: Checker, method: str, where: str, lead: str = "") -> str:
    if method not in names():
        near = difflib.get_close_matches(method, names(), n=1, cutoff=0.6)
        check.fail(where, lead + f"unknown method '{method}'; " + (f"did you mean '{near[0]}'? " if near else "")
                   + f"choose one of: {', '.join(names())}")
    return method


def load_sweep_file(path) -> SweepSpec | StudySpec | TransientSpec:
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


def ensure(name: str, results_dir="results", sweeps_dir="sweeps", *, workers: int | str = "auto"):
    """Results of the sweep file ``sweeps/<name>.toml``, from ``<results_dir>/<name>.nc``
    when that file was made from the same sweep file text, else computed and written
    (a file made from another version of the sweep file is replaced).

    A speed sweep gives its xarray Dataset; a continuation study gives its branches
    ({"frequency": Branch, "parameter": ..., "period_doubled": ...}, see
    :mod:`periodyn.studies.continuation`); a transient study its Dataset of time histories (see
    :mod:`periodyn.studies.transient`). Relative directories are taken from the project root (the
    folder holding ``sweeps/``). Used by the figure scripts, which only read results and draw.
    """
    root = project_root()
    spec = load_sweep_file(root / sweeps_dir / f"{name}.toml")
    out = root / results_dir / f"{name}.nc"
    if isinstance(spec, StudySpec):
        return ensure_study(spec, out)
    if isinstance(spec, TransientSpec):
        return ensure_transient(spec, out)
    ds = load_if_made_from(out, "sweep_file_text", spec.text)
    return ds if ds is not None else sweep_file(spec, out=out, workers=workers, resume=True, progress=None)
