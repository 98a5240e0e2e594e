"""Speed sweeps: the ``[sweep]`` table of a study file (:class:`SweepSpec`) and its run
(:func:`run_sweep`, through :func:`periodyn.engine.front.sweep_file`).

Format (``[model]`` and ``description`` as in :mod:`periodyn.studies.spec`)::

    [sweep]
    omega = { start = 0.01, stop = 1.4, num = 1400, unit = "omega0" }
    # or   { values = [0.1, 0.2], unit = "rad/s" }
    harmonics = 12
    samples = 64                  # optional: samples per period (default: the builder's)
    stability = true              # optional: true (= "auto"), false, or a stability method:
                                  # auto | hill | sparse | dense | monodromy | magnus
    boundaries = true             # optional: refine the stability boundaries (1-D sweeps)
    output_units = { phi = "rad" }  # optional: unit of each output in the results
    quasistatic = 4               # optional: harmonics 1..4 of the quasistatic solution

    [sweep.grid]                  # optional: a grid over builder parameters
    zeta = [0.005, 0.01, 0.02]    # or { start = 0.005, stop = 0.02, num = 4 }

``unit`` is "rad/s", "rpm", "Hz", or a reference frequency of the model: a ``metadata``
entry named omega* of the model built from ``[model.parameters]`` (e.g. "omega0").

With ``boundaries = true`` every sign change of ``max_real_exponent`` between neighbouring
speeds is refined by :func:`periodyn.stability.boundaries.stability_boundaries` and stored
in the result along the dimension ``boundary``: ``boundary_omega`` (rad/s),
``boundary_kind`` (fold | period-doubling | neimark-sacker), ``boundary_becomes_stable`` and
``boundary_message`` (why a refinement is not reliable: a truncated Hill verdict, a failure; '' if clean).

With ``quasistatic = N`` the result holds ``quasistatic_amplitude`` (grid..., omega,
quasistatic_harmonic, output): the amplitudes 2 |G_0 K_0^-1 f_k|, k = 1..N, of the
quasistatic solution (harmonic k of the forcing through the mean stiffness K_0, mapped by
the mean output map G_0) at every speed and grid point, a reference beside the harmonics.
"""

from __future__ import annotations

import difflib
import functools
import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr

from . import cache
from .checks import FIXED_UNITS, MAX_POINTS, Checker, FileSpec, builder_parameters, parameter_check
from ..engine.job import reference_frequencies
from ..errors import InputError
from ..stability.methods import names

__all__ = ["SweepSpec", "SweepPlan", "parse_sweep_table", "run_sweep", "MAX_HARMONICS"]

#: Harmonics a sweep file may ask for: the Hill matrix has (2m+1)·2n rows per speed.
MAX_HARMONICS = 1000
MAX_SAMPLES = 4 * MAX_HARMONICS + 1  # the stability methods sample the coefficients at about as many angles
_KEYS = ("omega", "harmonics", "samples", "stability", "method", "boundaries", "grid", "output_units", "quasistatic")


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
    output_units: {output: unit} for the results (empty: the model's); boundaries: refine
    the stability boundaries."""

    omega: dict[str, Any]
    omega_unit: str
    harmonics: int
    samples: int | None
    stability: bool
    method: str
    grid: dict[str, list]
    output_units: dict[str, str] = field(default_factory=dict)
    boundaries: bool = False
    quasistatic: int = 0

    @property
    def kind(self) -> str:
        """"sweep"."""
        return "sweep"

    def build(self, **overrides):
        """The model from [model.parameters] (and ``overrides``); builder errors become
        InputError naming the file. Without overrides, from the built-model cache where it
        holds it (:func:`~periodyn.studies.cache.cached_model`)."""
        if overrides:
            return self._build(**overrides)
        resample = (functools.partial(_resampled, self.builder, dict(self.parameters))
                    if "samples" in builder_parameters(self.builder) else None)
        return cache.cached_model(self, self._build, resample)

    def _build(self, **overrides):
        kwargs = {**self.parameters, **overrides}
        if self.samples is not None and "samples" in builder_parameters(self.builder):
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
            if self.samples is not None and "samples" in builder_parameters(self.builder):
                fixed["samples"] = self.samples
            for name, values in self.grid.items():  # every grid point must build
                for value in (values[0], values[-1]):
                    self.build(**{name: value})
            return SweepPlan(functools.partial(self.builder, **fixed), omega, dict(self.grid), reference)
        return SweepPlan(model, omega, None, reference)


def _resampled(builder, parameters: dict, samples: int):
    """The model of ``builder(**parameters)`` at ``samples`` angles (a cached model's resampling)."""
    return builder(**parameters, samples=samples)


def parse_sweep_table(check: Checker, table, *, source, name, text, description, example, builder, parameters,
                      accepted, settable) -> SweepSpec:
    """Validate a [sweep] table (``check`` names the file; ``accepted``/``settable``: the
    builder's keyword parameters and those a grid may vary)."""
    sweep = check.table(table, "[sweep]")
    check.keys(sweep, "[sweep]", _KEYS, ("omega", "harmonics"))
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
    if samples is not None and samples > MAX_SAMPLES:
        check.fail("[sweep] samples", f"{samples} samples per period is more than a sweep needs (at most {MAX_SAMPLES}, "
                                      f"4 x the harmonics limit + 1); use samples = {4 * harmonics + 1}")
    if samples is not None and samples < 2 * harmonics + 1:
        check.fail("[sweep] samples", f"{samples} samples cannot resolve {harmonics} harmonics; "
                                      f"use samples >= {2 * harmonics + 1} (>= {4 * harmonics + 1} recommended)")
    stability, method = _stability(check, sweep)

    grid_table = check.table(sweep.get("grid", {}), "[sweep.grid]")
    if grid_table and not settable:
        check.fail("[sweep.grid]", f"'{example}' has no parameters to vary; a grid needs an example builder "
                                   "(example = \"<name>\") with keyword parameters")
    check.keys(grid_table, f"[sweep.grid] (parameters of {example})", settable)
    grid = {k: check.values(v, f"[sweep.grid] {k}", parameter_check(check, accepted[k]))
            for k, v in grid_table.items()}
    points = math.prod(len(v) for v in grid.values()) * (omega_spec.get("num") or len(omega_spec.get("values", [])))
    if points > MAX_POINTS:
        check.fail("[sweep.grid]", f"{points} points is more than {MAX_POINTS}; split the sweep")
    boundaries = check.boolean(sweep.get("boundaries", False), "[sweep] boundaries")
    if boundaries and (grid or not stability):
        check.fail("[sweep] boundaries", "stability boundaries need stability = true and a sweep over omega "
                                         "alone (no [sweep.grid])")
    quasistatic = check.integer(sweep.get("quasistatic", 0), "[sweep] quasistatic", 0)
    if quasistatic > harmonics:
        check.fail("[sweep] quasistatic", f"{quasistatic} quasistatic harmonics exceed the sweep's {harmonics}; "
                                          f"give at most {harmonics}")
    return SweepSpec(source, name, text, description, example, builder, parameters, omega_spec, unit,
                     harmonics, samples, stability, method, grid, output_units, boundaries, quasistatic)


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


def run_sweep(spec: SweepSpec, out, *, omega=None, resume: bool = False, workers: int | str = 1, scheduler=None,
              progress=None, chunk_size: int | None = None, **_unused) -> xr.Dataset:
    """Run ``spec`` and write ``out`` (its boundaries too, with ``boundaries = true``) ->
    Dataset; with ``resume`` a current ``out`` is read and one made otherwise refused
    (:mod:`periodyn.studies.cache`)."""
    from ..engine import front
    from ..engine.session import sweep_guard
    from ..results import load, save

    with sweep_guard(out):  # one lock on out from the check of a finished file to the last write
        if cache.finished(out, spec, omega, resume):
            return load(out)
        ds = front.sweep_file(spec, omega=omega, out=out, workers=workers, scheduler=scheduler, resume=resume,
                              progress=progress, chunk_size=chunk_size)
        if spec.boundaries:
            ds = ds.merge(_boundaries(spec, ds))
        if spec.quasistatic:
            ds = ds.merge(_quasistatic(spec, ds))
        ds.attrs.update(cache.stamp(spec, omega))
        save(ds, out)
        return ds


def _boundaries(spec: SweepSpec, ds: xr.Dataset) -> xr.Dataset:
    """Stability boundaries between neighbouring speeds of ``ds`` whose max Re(lambda)
    changes sign, each refined by Brent's method (increasing omega). A refinement that met
    a truncated Hill verdict, or failed (its omega then NaN), keeps its reason in
    ``boundary_message`` ('' where clean) and warns: never a traceback after the sweep."""
    from ..errors import ConvergenceError
    from ..stability.boundaries import StabilityBoundary, stability_boundaries
    from ..stability.floquet import TruncationWarning

    model = spec.build()
    system_at = getattr(model, "at", model)
    order = np.argsort(ds["omega"].values, kind="stable")
    omega, growth = ds["omega"].values[order], ds["max_real_exponent"].values[order]
    found, reasons = [], []
    for i in np.flatnonzero(np.sign(growth[:-1]) * np.sign(growth[1:]) < 0):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", TruncationWarning)
            try:
                pair = stability_boundaries(system_at, omega[i:i + 2], spec.harmonics, spec.method, truncation="warn")
                reason = next((str(w.message) for w in caught if issubclass(w.category, TruncationWarning)), "")
            except ConvergenceError as exc:
                pair, reason = [StabilityBoundary(math.nan, "", bool(growth[i + 1] < 0))], f"refinement failed: {exc}"
        found += pair
        reasons += [reason] * len(pair)
    flagged = [r for r in reasons if r]
    if flagged:
        warnings.warn(f"{len(flagged)} of {len(reasons)} stability boundaries are not reliable (boundary_message): "
                      f"{flagged[0]}", TruncationWarning, stacklevel=2)
    return xr.Dataset({"boundary_omega": ("boundary", [b.omega for b in found], {"units": "rad/s"}),
                       "boundary_kind": ("boundary", np.array([b.kind for b in found], dtype=object)),
                       "boundary_becomes_stable": ("boundary", [b.becomes_stable for b in found]),
                       "boundary_message": ("boundary", np.array(reasons, dtype=object))})


def _quasistatic(spec: SweepSpec, ds: xr.Dataset) -> xr.Dataset:
    """``quasistatic_amplitude`` (module docstring) at the speeds and grid points of ``ds``."""
    grid = list(spec.grid)
    orders = np.arange(1, spec.quasistatic + 1)
    shape = [len(spec.grid[g]) for g in grid]
    values = None
    for index in np.ndindex(*shape):
        model = spec.build(**{g: spec.grid[g][i] for g, i in zip(grid, index)})
        for j, omega in enumerate(ds["omega"].values):
            spectra = getattr(model, "at", lambda w: model)(float(omega)).spectra
            K = (spectra.stiffness.shape[0] - 1) // 2
            G0, K0 = spectra.outputs[(spectra.outputs.shape[0] - 1) // 2].real, spectra.stiffness[K].real
            forced = np.linalg.solve(K0, spectra.force[K + orders].T)      # (n, N)
            row = 2.0 * np.abs(G0 @ forced).T                              # (N, n_out)
            if values is None:
                values = np.empty((*shape, ds.sizes["omega"], *row.shape))
            values[(*index, j)] = row
    return xr.Dataset({"quasistatic_amplitude": ((*grid, "omega", "quasistatic_harmonic", "output"), values,
                                                 {"description": "2 |G_0 K_0^-1 f_k|: harmonic k of the forcing "
                                                                 "through the mean stiffness and output map"})},
                      coords={"quasistatic_harmonic": orders})
