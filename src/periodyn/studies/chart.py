"""Stability-chart studies: study files with a ``[chart]`` table, the stability boundaries
of a rheo-linear example followed over one of its parameters
(:func:`periodyn.stability.charts.stability_chart`).

Format (``[model]`` and ``description`` as in :mod:`periodyn.studies.spec`)::

    [chart]
    parameter = { name = "alpha", start = 0.02, stop = 0.785398, num = 16 }  # a builder keyword
    # or        { name = "zeta", values = [0.005, 0.01, 0.02] }
    omega = { start = 0.5, stop = 0.99, num = 25, unit = "omega_b" }   # the speed window and the
                                  # seeds' bisection grid; unit as in [sweep]
    harmonics = 12
    samples = 64                  # optional: samples per period (default: the builder's)
    seeds = [0.785398]            # optional: parameter values (of the grid) where the boundaries are
                                  # found by bisection and followed from (default: both grid ends)
    stability = "auto"            # optional: the stability method (default "auto")
    checks = 3                    # optional: monodromy checks per boundary (default 0)
    xtol = 1e-9                   # optional: relative tolerance in omega of the boundary points
    ptol = 1e-7                   # optional: tolerance of a tip in p, relative to the parameter range

Results: one netCDF file, the chart's dataset (:mod:`periodyn.stability.chart_data`) with
attributes ``model``, ``description``, ``omega_unit`` and ``reference_frequency`` (rad/s;
1 for a fixed unit), the package versions and the cache fingerprint
(:mod:`periodyn.studies.cache`).
"""

from __future__ import annotations

import functools
import json
from dataclasses import dataclass

import numpy as np
import xarray as xr

from . import cache
from .checks import FIXED_UNITS, Checker, FileSpec, builder_parameters
from .sweep import MAX_HARMONICS
from ..errors import InputError
from ..stability.methods import names

__all__ = ["ChartSpec", "parse_chart", "run_chart", "chart_summary"]

_KEYS = ("parameter", "omega", "harmonics", "samples", "seeds", "stability", "checks", "xtol", "ptol")
_MAX_GRID = 10_000


@dataclass(frozen=True)
class ChartSpec(FileSpec):
    """A validated chart study: parameter name and grid (P,), speed window {start, stop,
    num} in ``omega_unit``, harmonics, samples or None, seeds (None: the grid ends),
    stability method, monodromy checks per boundary, xtol, ptol."""

    parameter_name: str
    parameter_grid: tuple[float, ...]
    omega: dict
    omega_unit: str
    harmonics: int
    samples: int | None
    seeds: tuple[float, ...] | None
    method: str
    checks: int
    xtol: float
    ptol: float

    @property
    def kind(self) -> str:
        """"chart"."""
        return "chart"

    def build(self, value: float):
        """The model from [model.parameters] with the chart's parameter at ``value``;
        builder errors become InputError naming the file."""
        kwargs = {**self.parameters, self.parameter_name: value}
        if self.samples is not None and "samples" in builder_parameters(self.builder):
            kwargs["samples"] = self.samples
        try:
            return self.builder(**kwargs)
        except InputError as exc:
            raise InputError(f"{self.source}: [model] {self.example} at {self.parameter_name} = {value:g}: {exc}") \
                from None
        except (TypeError, ValueError, ArithmeticError) as exc:
            raise InputError(f"{self.source}: [model] {self.example} cannot be built at {self.parameter_name} = "
                             f"{value:g} ({type(exc).__name__}: {exc}); check [chart] parameter") from None


def parse_chart(check: Checker, table, *, source, name, text, description, example, builder, parameters, accepted,
                settable) -> ChartSpec:
    """Validate a [chart] table (``check`` names the file; ``settable``: the builder
    keywords a chart may vary)."""
    c = check.table(table, "[chart]")
    check.keys(c, "[chart]", _KEYS, ("parameter", "omega", "harmonics"))
    par = check.table(c["parameter"], "[chart] parameter")
    if "name" not in par:
        check.fail("[chart] parameter", "missing name; add name = \"<builder keyword>\" (the parameter followed)")
    check.keys(par, "[chart] parameter", ("name", "values") if "values" in par else ("name", "start", "stop", "num"))
    pname = check.string(par["name"], "[chart] parameter.name")
    numeric = [k for k in settable if k != "samples" and isinstance(accepted[k].default, (int, float))
               and not isinstance(accepted[k].default, bool)]
    if pname not in numeric:
        check.fail("[chart] parameter.name", f"'{pname}' is not a numeric parameter of {example}; choose one of: "
                                             f"{', '.join(numeric) or 'none (use an example builder)'}")
    if pname in parameters:
        check.fail("[model.parameters]", f"{pname} is the chart's parameter; drop it from [model.parameters]")
    grid = check.values({k: v for k, v in par.items() if k != "name"} if "values" not in par else par["values"],
                        "[chart] parameter", check.number)
    if len(grid) < 2 or np.any(np.diff(grid) <= 0) or len(grid) > _MAX_GRID:
        check.fail("[chart] parameter", f"the grid must increase and hold 2 to {_MAX_GRID} values, got {len(grid)}")
    om = check.table(c["omega"], "[chart] omega")
    check.keys(om, "[chart] omega", ("start", "stop", "num", "unit"), ("start", "stop", "num", "unit"))
    speed = functools.partial(check.number, positive=True)
    omega = {"start": speed(om["start"], "[chart] omega.start"), "stop": speed(om["stop"], "[chart] omega.stop"),
             "num": check.integer(om["num"], "[chart] omega.num", 2)}
    if omega["stop"] <= omega["start"] or omega["num"] > _MAX_GRID:
        check.fail("[chart] omega", f"needs start < stop and at most {_MAX_GRID} speeds")
    harmonics = check.integer(c["harmonics"], "[chart] harmonics", 1)
    if harmonics > MAX_HARMONICS:
        check.fail("[chart] harmonics", f"{harmonics} harmonics is more than {MAX_HARMONICS}")
    samples = check.integer(c["samples"], "[chart] samples", 1) if "samples" in c else None
    if samples is not None and samples < 2 * harmonics + 1:
        check.fail("[chart] samples", f"{samples} samples cannot resolve {harmonics} harmonics; use samples >= "
                                      f"{2 * harmonics + 1}")
    seeds = None
    if "seeds" in c:
        seeds = tuple(check.values(c["seeds"], "[chart] seeds", check.number))
        off = [s for s in seeds if not np.any(np.isclose(grid, s, rtol=1e-12, atol=0))]
        if off:
            check.fail("[chart] seeds", f"{off} are not values of the parameter grid; give seeds from the grid")
        seeds = tuple(float(np.asarray(grid)[np.argmin(np.abs(np.asarray(grid) - s))]) for s in seeds)
    method = check.string(c.get("stability", "auto"), "[chart] stability")
    if method not in names():
        check.fail("[chart] stability", f"unknown method '{method}'; choose one of: {', '.join(names())}")
    checks = check.integer(c.get("checks", 0), "[chart] checks", 0)
    tolerances = {}
    for key, default in (("xtol", 1e-9), ("ptol", 1e-7)):
        tolerances[key] = check.number(c.get(key, default), f"[chart] {key}", positive=True)
        if tolerances[key] >= 1e-2:
            check.fail(f"[chart] {key}", f"must be below 1e-2 (a relative tolerance), got {tolerances[key]!r}")
    return ChartSpec(source, name, text, description, example, builder, parameters, pname, tuple(grid), omega,
                     check.string(om["unit"], "[chart] omega.unit"), harmonics, samples, seeds, method, checks,
                     tolerances["xtol"], tolerances["ptol"])


def _reference(spec: ChartSpec, models) -> float:
    """rad/s per unit of the speed window: a fixed unit, or a reference frequency the
    model has at both ends of the parameter grid (equal there)."""
    from ..engine.job import reference_frequencies

    if spec.omega_unit in FIXED_UNITS:
        return FIXED_UNITS[spec.omega_unit]
    refs = [reference_frequencies(models(p)) for p in (spec.parameter_grid[0], spec.parameter_grid[-1])]
    if spec.omega_unit not in refs[0]:
        raise InputError(f"{spec.source}: [chart] omega.unit: unknown unit '{spec.omega_unit}'; use one of: "
                         f"{', '.join([*FIXED_UNITS, *refs[0]])}")
    first, last = refs[0][spec.omega_unit], refs[1].get(spec.omega_unit)
    if last is None or not np.isclose(first, last, rtol=1e-10):
        raise InputError(f"{spec.source}: [chart] omega.unit: {spec.omega_unit} changes with {spec.parameter_name} "
                         f"({first:.8g} vs {last} rad/s); give the speeds in rad/s")
    return first


def run_chart(spec: ChartSpec, out, *, resume: bool = False, **_unused) -> xr.Dataset:
    """Compute the chart of ``spec`` (and its monodromy checks) and write ``out`` ->
    Dataset; with ``resume`` a current ``out`` is read and one made otherwise refused."""
    from ..results import load, package_versions, save
    from ..stability.chart_data import ChartOptions, chart_dataset
    from ..stability.charts import check_chart, stability_chart

    if cache.finished(out, spec, None, resume):
        return load(out)
    models = functools.lru_cache(maxsize=4)(spec.build)
    factor = _reference(spec, models)
    omega = np.linspace(spec.omega["start"], spec.omega["stop"], spec.omega["num"]) * factor
    options = ChartOptions(spec.harmonics, spec.method, spec.xtol, spec.ptol)
    chart = stability_chart(models, omega, spec.parameter_grid, options, seeds=spec.seeds, name=spec.parameter_name)
    checks = check_chart(models, chart, spec.checks) if spec.checks else ()
    ds = chart_dataset(chart, checks)
    ds.attrs.update({"model": spec.example, "description": spec.description, "omega_unit": spec.omega_unit,
                     "reference_frequency": factor, "chart_file_text": spec.text,
                     "versions": json.dumps(package_versions()), **cache.stamp(spec)})
    save(ds, out)
    return ds


def chart_summary(ds: xr.Dataset) -> list[str]:
    """Lines on a chart result: each boundary's extent, kinds and ends, its tips, and the
    monodromy checks."""
    ref, unit, name = float(ds.attrs["reference_frequency"]), ds.attrs["omega_unit"], ds.attrs["parameter_name"]
    lines = []
    for i in range(ds.sizes["boundary"]):
        mine = ds["curve"].values == i
        p, w, kind, side = (ds[v].values[mine] for v in ("parameter", "omega", "kind", "side"))
        tips = ", ".join(f"{name} = {q:.6g} at omega = {x / ref:.6g} {unit}" for q, x in zip(p[side == 0], w[side == 0]))
        lines.append(f"boundary {i}: {mine.sum()} points, {name} {p.min():.4g}..{p.max():.4g}, omega "
                     f"{w.min() / ref:.4g}..{w.max() / ref:.4g} {unit}, {'/'.join(dict.fromkeys(map(str, kind)))}, "
                     f"ends {ds['start'].values[i]} and {ds['stop'].values[i]}" + (f"; tip {tips}" if tips else ""))
    if ds.sizes.get("check", 0):
        agree = ds["check_agrees"].values
        lines.append(f"monodromy checks: {int(agree.sum())} of {agree.size} agree (stable outside, unstable inside, "
                     "same type)")
    return lines
