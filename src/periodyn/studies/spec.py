"""Study files (TOML): ONE dialect for every kind of study, parsed by :func:`parse_sweep`
(:func:`load_sweep_file` for a path), run by :func:`run` and read back, computed only when
not current (:mod:`periodyn.studies.cache`), by :func:`ensure`.

A study file holds an optional ``description``, a ``[model]`` and ONE table naming its
kind, with its schema and runner in a module of its own:

=================  ==========================================  ================================
table              what                                        module
=================  ==========================================  ================================
``[sweep]``        periodic solution and stability per speed   :mod:`periodyn.studies.sweep`
``[continuation]`` branches of a DAE (arc length, or speeds)   :mod:`periodyn.studies.continuation`
``[transient]``    the motion from rest at one speed           :mod:`periodyn.studies.transient`
``[campbell]``     rotor eigenvalues over spin speeds          :mod:`periodyn.studies.campbell`
``[chart]``        stability boundaries over a parameter       :mod:`periodyn.studies.chart`
=================  ==========================================  ================================

``[model]`` is one of::

    example = "pendulum"          # a builder in periodyn.examples
    [model.parameters]            # optional: keyword arguments of that builder
    zeta = 0.01

or a rotor file (``rotor = "rotors/table1.toml"``, relative to the study file; a
``[campbell]`` study only), or an element model (see :func:`element_model`):
planar or spatial: nodes, ``[[model.elements]]``, masses, rigid bodies, independent
elements, loads, ``fixed``, ``prescribed``, ``dynamic`` and ``[[model.outputs]]``
(:mod:`periodyn.studies.elements`; see ``sweeps/elliptic_pendulum_elements.toml``,
``sweeps/cardan_shaft_elements.toml``, ``sweeps/rotor_table1_elements.toml``).

Every problem raises :class:`InputError` whose message starts with the file name and the
table, and says what to change.
"""

from __future__ import annotations

import difflib
import functools
import tomllib
from pathlib import Path
from typing import Callable

from .. import examples
from . import cache
from .campbell import CampbellSpec, parse_campbell, run_campbell
from .chart import ChartSpec, parse_chart, run_chart
from .checks import FIXED_UNITS, Checker, builder_parameters, parameter_check
from .continuation import StudySpec, parse_continuation, run_study
from .elements import MODEL_FORM_KEYS, check_element_form, element_model, element_rotor
from .sweep import MAX_HARMONICS, SweepPlan, SweepSpec, parse_sweep_table, run_sweep
from .transient import TransientSpec, parse_transient, run_transient
from ..errors import InputError

__all__ = ["SweepSpec", "StudySpec", "TransientSpec", "CampbellSpec", "ChartSpec", "SweepPlan", "load_sweep_file", "parse_sweep",
           "project_root", "known_examples", "element_model", "run", "ensure", "ensure_result", "FIXED_UNITS",
           "MAX_HARMONICS", "KINDS"]

#: The study kinds: table name -> (parser of the table, runner).
KINDS = {"sweep": (parse_sweep_table, run_sweep), "continuation": (parse_continuation, run_study),
         "transient": (parse_transient, run_transient), "campbell": (parse_campbell, run_campbell),
         "chart": (parse_chart, run_chart)}
_WHAT = {"sweep": "a speed sweep", "continuation": "a continuation study of a DAE example",
         "transient": "the motion from rest at one speed", "campbell": "a rotor's Campbell diagram",
         "chart": "stability boundaries over a parameter"}


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


def _model(check: Checker, data: dict, name: str, kind: str) -> tuple:
    """(example, builder, accepted parameters, settable names, parameters, rotor file) of [model]."""
    from ..rotor import load_rotor

    model = check.table(data["model"], "[model]")
    rotor_file = None
    element_keys = [k for k in MODEL_FORM_KEYS if k in model and k != "name"]
    if "example" in model and element_keys:
        check.fail("[model]", f"give either example = \"<name>\" or an element model ({', '.join(element_keys)}), "
                              "not both")
    if "rotor" in model:
        check.keys(model, "[model] (a rotor file: rotor = \"<path>\")", ("rotor", "parameters"), ("rotor",))
        path = Path(check.string(model["rotor"], "[model] rotor"))
        rotor_file = str(path if path.is_absolute() else Path(check.source).parent / path)
        if not Path(rotor_file).is_file():
            check.fail("[model] rotor", f"no rotor file at {rotor_file} (paths are relative to the study file)")
        example, builder = path.stem, functools.partial(load_rotor, rotor_file)
        accepted = builder_parameters(load_rotor)
        settable = ("elements",)
    elif "example" in model or not element_keys:
        check.keys(model, "[model] (use example = \"<name>\" or declare points and [[model.elements]])",
                   ("example", "parameters"), ("example",))
        example = check.string(model["example"], "[model] example")
        builders = known_examples()
        if example not in builders:
            near = difflib.get_close_matches(example, builders, n=1, cutoff=0.6)
            hint = f"did you mean '{near[0]}'? " if near else ""
            check.fail("[model] example", f"unknown example '{example}'; {hint}known examples: {', '.join(builders)}")
        builder = builders[example]
        accepted = builder_parameters(builder)
        settable = tuple(k for k in accepted if k != "samples")
    else:
        table = check_element_form(check, model)
        example = table["name"] if "name" in model else name
        if (kind == "campbell") != ("stations" in table):
            check.fail("[model] stations", "a [campbell] study of an element model needs stations = [<points on the "
                                           "shaft>] (and only it)" if kind == "campbell" else
                       "stations are for a [campbell] study of a spatial rotor; drop them here")
        build = element_rotor if kind == "campbell" else element_model
        builder = functools.partial(build, table, name=example)
        accepted, settable = {"samples": None}, ()

    parameters = check.table(model.get("parameters", {}), "[model.parameters]")
    if "samples" in parameters:
        check.fail("[model.parameters]", "give samples in [sweep] (samples = ...), not as a model parameter")
    check.keys(parameters, f"[model.parameters] of {example}", settable)
    parameters = {k: parameter_check(check, accepted[k])(v, f"[model.parameters] {k}") for k, v in parameters.items()}
    return example, builder, accepted, settable, parameters, rotor_file


def parse_sweep(text: str, source: str = "<sweep file>", name: str = "sweep"):
    """Validate study-file text -> the spec of its kind (:class:`SweepSpec`,
    :class:`StudySpec`, :class:`TransientSpec` or :class:`CampbellSpec`; ``spec.kind``
    tells which); raises InputError with the nearest fix."""
    check = Checker(source)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source}: not valid TOML: {exc}") from None
    check.keys(data, "top level", ("description", "model", *KINDS), ("model",))
    given = [k for k in KINDS if k in data]
    if not given:
        check.fail("top level", "missing required key " + ", ".join(f"'{k}' ({what})" for k, what in _WHAT.items()))
    if len(given) > 1:
        check.fail("top level", f"give one of {', '.join(f'[{k}] ({_WHAT[k]})' for k in KINDS)}, "
                                f"not {' and '.join(f'[{k}]' for k in given)}")
    kind = given[0]
    description = check.string(data.get("description", ""), "description")
    example, builder, accepted, settable, parameters, rotor_file = _model(check, data, name, kind)
    if rotor_file is not None and kind != "campbell":
        check.fail("[model] rotor", "a rotor file is the model of a [campbell] study; use an example or an "
                                    "element model here")
    common = dict(source=source, name=name, text=text, description=description, example=example, builder=builder,
                  parameters=parameters)
    if kind == "campbell":
        return parse_campbell(check, data[kind], **common, accepted=accepted, settable=settable,
                              rotor_file=rotor_file)
    if kind in ("sweep", "chart"):
        return KINDS[kind][0](check, data[kind], **common, accepted=accepted, settable=settable)
    return KINDS[kind][0](check, data[kind], **common)


def load_sweep_file(path):
    """Read and validate ``path`` (a .toml study file of any kind)."""
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


def run(spec, out, **options):
    """Run a parsed study of any kind and write its result to ``out``; options: omega
    (start, stop, num in the file's unit, replacing its range), resume, progress, and
    for a sweep workers, scheduler, chunk_size."""
    return KINDS[spec.kind][1](spec, Path(out), **options)


def ensure(name: str, results_dir="results", sweeps_dir="sweeps", *, workers: int | str = "auto"):
    """The result of the study file ``sweeps/<name>.toml`` from ``<results_dir>/<name>.nc``
    when that file is current (:mod:`periodyn.studies.cache`), else computed and written
    (a file made otherwise is replaced).

    A speed sweep, transient, Campbell or chart study gives its xarray Dataset; a continuation
    study its branches ({"frequency": Branch, ...}). Relative directories are taken from
    the project root (the folder holding ``sweeps/``). Used by the figure scripts, which
    only read results and draw.
    """
    import sys

    root = project_root()
    spec = load_sweep_file(root / sweeps_dir / f"{name}.toml")
    progress = sys.stderr if spec.kind == "continuation" else None
    return ensure_result(spec, root / results_dir / f"{name}.nc", workers=workers, progress=progress)


def ensure_result(spec, out, **options):
    """The result of the parsed study ``spec`` from ``out`` when current, else computed
    there (a file made otherwise is replaced); options as for :func:`run`."""
    cache.discard_stale(out, spec, options.get("omega"))
    return run(spec, out, resume=True, **options)
