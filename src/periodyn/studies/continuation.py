"""Continuation studies: sweep files with a ``[continuation]`` table instead of ``[sweep]``.

Format (``[model]`` and ``description`` as in :mod:`periodyn.studies.spec`; the example must build
a ``periodyn.DAE``)::

    [continuation]
    omega = { start = 2.5, stop = 5.0, unit = "rad/s" }   # unit: rad/s, rpm or Hz
    # or    { values = [150.0, 200.0], unit = "rad/s" }: solutions at these speeds only
    harmonics = 10
    method = "ihb"                # optional: ihb | shooting
    stability = "magnus"          # optional: a periodyn.nonlinear.orbit_linearization method, or false
    subharmonic = 1               # optional: orbit period 2 pi nu / omega
    ds_max = 0.1                  # optional: largest arc-length step
    max_points = 800              # optional: points per branch at most
    tol = 1e-5                    # optional: residual max-norm of a point (SI units of the equations)
    confirm = "truncation"        # optional: check each special point against more harmonics (orbit defect, re-solve
                                  # at H + 4); true: also integrate the survivors (slow for big models)
    parameter = { name = "f", start = 0.01, stop = 0.3, omega = 3.6 }   # optional curve at fixed omega
    period_doubling = { ds_max = 0.05, max_points = 150 }  # optional: follow the 2T branch
    time_history = { omega = 3.6, start = "steady_state" }  # optional: an orbit against integration
    output_samples = 64           # optional, element models: their outputs along every orbit

Every omega of the table (the parameter curve's and time_history's too) is in omega.unit.
``time_history`` and ``output_samples``: :mod:`periodyn.studies.orbits` (what the figures
draw, computed here so that figure scripts only read).

With ``omega.values`` the "frequency" branch holds one periodic solution per given speed
(in the order given), each by Newton from a start of its own (below), with no arc-length
steps in between: for stiff element models whose response over a wide speed range passes
resonances and unstable zones that a continuation would have to resolve point by point.
Method "shooting" shoots element models on the implicit one-period map (``shooting(...,
integrator="implicit")``, multipliers of its monodromy) from the linearized harmonic-balance
orbit at each speed, other DAEs with DOP853; "ihb" solves EGA-IHB with the stability
method of the table. No parameter curve or period-doubled branch with given speeds.

``periodyn sweep FILE`` computes the frequency branch (``continuation`` from omega.start to
omega.stop), the parameter curve and the period-doubled branch (born at the lowest-omega
period-doubling point of the frequency branch, followed to omega.stop) and writes ONE
netCDF file: the root group holds the study attributes (file text, settings, branch names,
notes), each branch is a group ("frequency", "parameter", "period_doubled") written by
``Branch.to_dataset`` (with its element outputs, ``output_samples``), and the group
"time_history" holds the orbit against integration. :func:`load_study` reads the
branches back as {name: Branch}; ``periodyn.results.load_groups`` reads every group.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from . import cache
from .checks import FIXED_UNITS, Checker, FileSpec
from .orbits import branch_outputs, check_time_history, element_model_of, orbit_time_history
from ..errors import InputError

__all__ = ["StudySpec", "parse_continuation", "run_study", "load_study"]

_KEYS = ("omega", "harmonics", "method", "stability", "subharmonic", "ds_max", "max_points", "tol", "confirm",
         "parameter", "period_doubling", "time_history", "time_history_omega", "output_samples")
_METHODS = ("ihb", "shooting")


@dataclass(frozen=True)
class StudySpec(FileSpec):
    """A validated continuation study. omega: (start, stop) in ``omega_unit``; parameter:
    {name, start, stop, omega} or None; period_doubling: continuation options of the 2T
    branch or None (no 2T branch); options: ContinuationOptions values from the file;
    time_history: the validated table (omega in ``omega_unit``) or None; output_samples:
    samples per period of the element outputs stored per point, or None
    (:mod:`periodyn.studies.orbits`)."""

    omega: tuple[float, float]
    omega_unit: str
    harmonics: int
    method: str
    options: dict[str, Any]
    parameter: dict[str, Any] | None
    period_doubling: dict[str, Any] | None
    time_history: dict[str, Any] | None
    speeds: tuple[float, ...] | None = None
    output_samples: int | None = None

    @property
    def kind(self) -> str:
        """"continuation" (a SweepSpec says "sweep")."""
        return "continuation"

    def build(self):
        """The DAE from [model.parameters]; builder errors become InputError naming the file."""
        from ..dae import DAE

        try:
            system = self.builder(**self.parameters)
        except (TypeError, ValueError, ArithmeticError, InputError) as exc:
            raise InputError(f"{self.source}: [model] {self.example} cannot be built from these parameters "
                             f"({type(exc).__name__}: {exc}); check [model.parameters]") from None
        if not isinstance(system, DAE):
            raise InputError(f"{self.source}: [continuation]: {self.example} is not a DAE example; use [sweep] "
                             "for a speed sweep, or a DAE example (rod_pendulum, inverted_pendulum, ...)")
        return system

    def omega_range(self, omega: tuple | None = None) -> tuple[float, float]:
        """(start, stop) rad/s; ``omega`` (start, stop[, num]) in the file's unit replaces the file's."""
        start, stop = self.omega if omega is None else (float(omega[0]), float(omega[1]))
        factor = FIXED_UNITS[self.omega_unit]
        return start * factor, stop * factor

    def speed_values(self, omega: tuple | None = None) -> np.ndarray | None:
        """The given speeds (k,) rad/s (None for a continuation); ``omega`` (start, stop,
        num) in the file's unit replaces them by num equally spaced speeds."""
        if self.speeds is None:
            return None
        values = self.speeds if omega is None else np.linspace(*(float(v) for v in omega[:2]), int(omega[2]))
        return np.asarray(values, float) * FIXED_UNITS[self.omega_unit]

    def extent(self, omega: tuple | None = None) -> list | None:
        """The range replacing the file's as it changes the result: (start, stop) of a
        continuation (its steps choose the points), (start, stop, num) of given speeds."""
        if omega is None:
            return None
        return [float(v) for v in (omega if self.speeds is not None else omega[:2])]


def parse_continuation(check: Checker, table, *, source, name, text, description, example, builder,
                       parameters) -> StudySpec:
    """Validate a [continuation] table (``check`` names the file)."""
    from ..stability.methods import names

    c = check.table(table, "[continuation]")
    check.keys(c, "[continuation]", _KEYS, ("omega", "harmonics"))
    om = check.table(c["omega"], "[continuation] omega")
    speeds = None
    speed = lambda v, where: check.number(v, where, positive=True)  # noqa: E731
    if "values" in om:
        check.keys(om, "[continuation] omega", ("values", "unit"), ("values", "unit"))
        speeds = tuple(check.values(om["values"], "[continuation] omega.values", speed))
        omega = (min(speeds), max(speeds))
        for key in ("parameter", "period_doubling"):
            if key in c:
                check.fail(f"[continuation] {key}", "needs a continuation over omega = { start, stop }, not "
                                                    "given speeds (omega.values)")
    else:
        check.keys(om, "[continuation] omega", ("start", "stop", "unit"), ("start", "stop", "unit"))
        omega = (speed(om["start"], "[continuation] omega.start"), speed(om["stop"], "[continuation] omega.stop"))
        if omega[0] == omega[1]:
            check.fail("[continuation] omega", "start and stop are equal; give a range to continue over")
    unit = check.string(om["unit"], "[continuation] omega.unit")
    if unit not in FIXED_UNITS:
        check.fail("[continuation] omega.unit", f"unknown unit '{unit}'; use one of: {', '.join(FIXED_UNITS)}")
    harmonics = check.integer(c["harmonics"], "[continuation] harmonics", 1)
    if harmonics > 200:
        check.fail("[continuation] harmonics", f"{harmonics} harmonics is more than a continuation can afford "
                                               "(at most 200); 5-20 resolve the papers' examples")
    method = check.string(c.get("method", "ihb"), "[continuation] method")
    if method not in _METHODS:
        check.fail("[continuation] method", f"unknown method '{method}'; choose one of: {', '.join(_METHODS)}")
    options = _options(check, c, "[continuation]")
    stability = c.get("stability", "magnus")
    if stability is False:
        options["stability"] = None
    elif not isinstance(stability, str) or stability not in names():
        choices = ("magnus", *(name for name in names() if name != "magnus"))  # the default first
        check.fail("[continuation] stability", f"must be one of {', '.join(choices)} or false, "
                                               f"got {stability!r}")
    else:
        options["stability"] = stability
    if "confirm" in c:
        if c["confirm"] != "truncation":
            check.boolean(c["confirm"], "[continuation] confirm (true, false or \"truncation\")")
        options["confirm"] = c["confirm"]
    if "subharmonic" in c:
        options["subharmonic"] = check.integer(c["subharmonic"], "[continuation] subharmonic", 1)
    parameter = None
    if "parameter" in c:
        where = "[continuation] parameter"
        p = check.table(c["parameter"], where)
        check.keys(p, where, ("name", "start", "stop", "omega"), ("name", "start", "stop", "omega"))
        pname = check.string(p["name"], f"{where}.name")
        if pname not in parameters:
            check.fail(f"{where}.name", f"'{pname}' is not set in [model.parameters]; continue one of: "
                                        f"{', '.join(parameters) or '(none set)'}")
        parameter = {"name": pname, "start": check.number(p["start"], f"{where}.start"),
                     "stop": check.number(p["stop"], f"{where}.stop"), "omega": speed(p["omega"], f"{where}.omega")}
    period_doubling = None
    if "period_doubling" in c:
        if method != "ihb":
            check.fail("[continuation] period_doubling", "branch switching needs method = \"ihb\"")
        period_doubling = _options(check, check.table(c["period_doubling"], "[continuation] period_doubling"),
                                   "[continuation] period_doubling", strict=True)
    th = check_time_history(check, c, speed)
    if th is not None and th["branch"] == "period_doubled" and period_doubling is None:
        check.fail("[continuation] time_history.branch", "\"period_doubled\" needs period_doubling = { ... }")
    samples = c.get("output_samples")
    samples = None if samples is None else check.integer(samples, "[continuation] output_samples", 2)
    return StudySpec(source, name, text, description, example, builder, parameters, omega, unit, harmonics,
                     method, options, parameter, period_doubling, th, speeds, samples)


def _options(check: Checker, table: dict, where: str, strict: bool = False) -> dict:
    """ds_max, max_points and tol of a table (``strict``: no other keys than the first two)."""
    if strict:
        check.keys(table, where, ("ds_max", "max_points"))
    out = {}
    if "ds_max" in table:
        out["ds_max"] = check.number(table["ds_max"], f"{where} ds_max", positive=True)
    if "max_points" in table:
        out["max_points"] = check.integer(table["max_points"], f"{where} max_points", 2)
    if "tol" in table:
        out["tol"] = check.number(table["tol"], f"{where} tol", positive=True)
    return out


# ----------------------------------------------------------------------------- running
def run_study(spec: StudySpec, out, *, omega: tuple | None = None, resume: bool = False, progress=None,
              **_unused) -> dict:
    """Compute the branches of ``spec`` and write them to ``out`` -> {name: Branch}.

    omega: (start, stop[, num]) in the file's unit replacing the file's range (num is
    ignored: the arc-length steps choose the points). resume: a current ``out`` is read
    instead; one made otherwise is refused (InputError, :mod:`periodyn.studies.cache`).
    progress: None (quiet) or a text stream for one progress line per branch.
    """
    from ..arclength import continuation, switch_period_doubling
    from .points import solve_at_speeds

    out = Path(out)
    if cache.finished(out, spec, omega, resume):
        return load_study(out)
    system = spec.build()
    model = None if spec.output_samples is None else element_model_of(system)
    if spec.output_samples is not None and (model is None or not model.outputs):
        raise InputError(f"{spec.source}: [continuation] output_samples: {spec.example} is not an element model "
                         "with outputs; drop output_samples")
    a, b = spec.omega_range(omega)
    H, notes = spec.harmonics, []

    def run(label, compute, *args, **kw):
        axis = f"{spec.parameter['name']} =" if label == "parameter" else "omega ="
        unit = "" if label == "parameter" else " rad/s"
        live = progress is not None and getattr(progress, "isatty", lambda: False)()
        report = None if not live else (
            lambda n, v: print(f"\r{spec.name} {label}: {n} points, {axis} {v:.5g}{unit} ", end="", file=progress,
                               flush=True))
        branch = compute(*args, progress=report, **kw)
        if progress is not None:
            print(f"\r{spec.name} {label}: {len(branch)} points, ended: {branch.status or 'reached the stop'}",
                  file=progress, flush=True)
        return branch

    speeds = spec.speed_values(omega)
    if speeds is not None:
        branches = {"frequency": run("frequency", solve_at_speeds, system, speeds, H, spec.method, **spec.options)}
    else:
        branches = {"frequency": run("frequency", continuation, system, (a, b), H, spec.method, **spec.options)}
    if spec.parameter is not None:
        p = spec.parameter
        omega_p = p["omega"] * FIXED_UNITS[spec.omega_unit]
        branches["parameter"] = run("parameter", continuation, system, omega_p, H, spec.method,
                                    (p["name"], p["start"], p["stop"]), **spec.options)
    if spec.period_doubling is not None:
        pds = branches["frequency"].points("period-doubling")
        if pds:
            kw = {**spec.options, **spec.period_doubling}
            kw.pop("subharmonic", None)
            first = min(pds, key=lambda s: s.omega)
            branches["period_doubled"] = run("period_doubled", switch_period_doubling, branches["frequency"], first,
                                             b, **kw)
        else:
            notes.append("no period-doubling point on the frequency branch: no period_doubled branch")
    groups = _groups(spec, system, model, branches, notes, progress)
    _write(out, spec, cache.stamp(spec, omega), branches, groups, notes)
    return branches


def _groups(spec: StudySpec, system, model, branches: dict, notes: list[str], progress) -> dict:
    """The result's groups: each branch (with the model's numeric metadata, and its element
    outputs with ``output_samples``) and the time history (:mod:`periodyn.studies.orbits`;
    none, with a note, when its branch was not found)."""
    metadata = {k: float(v) for k, v in (getattr(system, "metadata", None) or {}).items()
                if isinstance(v, (int, float)) and not isinstance(v, bool)}
    groups = {}
    for key, branch in branches.items():
        ds = branch.to_dataset()
        ds.attrs["model_metadata"] = json.dumps(metadata, sort_keys=True)  # e.g. reference frequencies (rad/s)
        groups[key] = ds if model is None else ds.merge(branch_outputs(model, branch, spec.output_samples))
    if spec.time_history is not None and spec.time_history["branch"] not in branches:
        notes.append(f"no {spec.time_history['branch']} branch: no time history")
    elif spec.time_history is not None:
        th = orbit_time_history(system, branches, spec.time_history,
                                spec.time_history["omega"] * FIXED_UNITS[spec.omega_unit], spec.harmonics)
        groups["time_history"] = th
        if progress is not None:
            print(f"{spec.name} time_history: omega = {th.attrs['omega']:.5g} rad/s, integration deviates "
                  f"{th.attrs['deviation']:.2e} from the orbit", file=progress, flush=True)
    return groups


def _write(out: Path, spec: StudySpec, stamp: dict, branches: dict, groups: dict, notes: list[str]) -> None:
    """One netCDF file: study attributes in the root group, one group per branch and the
    time history (atomic, checksummed as every result file: :func:`periodyn.results.save`)."""
    from ..results import package_versions, save

    attrs = {"study": spec.name, "model": spec.example, "description": spec.description,
             "study_file_text": spec.text, "branches": ",".join(branches),
             "notes": "; ".join(notes), "versions": json.dumps(package_versions()), **stamp}
    save(xr.Dataset(attrs=attrs), out, groups)


def _read(path: Path) -> dict:
    from ..arclength import Branch
    from ..results import load_groups

    root, groups = load_groups(path)
    if "branches" not in root.attrs:
        raise InputError(f"{path} is not a continuation study result (no branches); was it made by a speed "
                         "sweep? give another --out file")
    try:
        return {key: Branch.from_dataset(groups[key]) for key in root.attrs["branches"].split(",")}
    except (ValueError, KeyError) as exc:
        raise InputError(f"{path} is not a readable periodyn study file ({type(exc).__name__}: {exc})") from None


def load_study(path) -> dict:
    """Branches of a study file written by :func:`run_study`, {name: Branch}."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"no study result at {path}; run the study first (periodyn sweep FILE --out {path})")
    return _read(path)
