"""Transient studies: sweep files with a ``[transient]`` table instead of ``[sweep]``, the
motion from rest over the first periods at one speed (Schwab & Meijaard 2001, Fig. 4).

Format (``[model]`` and ``description`` as in :mod:`periodyn.studies.spec`)::

    [transient]
    omega = { value = 150.0, unit = "rad/s" }   # unit: rad/s, rpm or Hz
    harmonics = 12      # a rheo-linear model: harmonics of its periodic solution
    periods = 1.0       # optional: time span in periods 2 pi / omega (default 1)
    points = 401        # optional: equally spaced times from 0 (default 401)
    samples = 64        # optional: samples per period of a rheo-linear builder
    rtol = 1e-9         # optional: tolerances of the direct integration of a DAE
    atol = 1e-11

The motion starts at rest: ``q(0) = q'(0) = 0`` for a rheo-linear model (the nominal
motion), ``q(0) = q0`` (the DAE's reference, the undeformed mechanism for element models)
and ``q'(0) = 0`` for a DAE. A rheo-linear example (an
``OmegaSplitModel``) gives its periodic solution and the complete solution by averaging
(eq. 24) and by direct integration; a non-linear example (a ``periodyn.DAE``) gives the
motion by direct integration, as outputs of its element model when it has one
(:func:`periodyn.nonlinear.element_outputs`), else as its coordinates.

Results: one netCDF file read by :func:`periodyn.studies.spec.ensure`, an xarray Dataset with
coordinates ``time`` (s), ``method`` and ``output``; ``outputs`` (method, time, output) and,
for a rheo-linear model, ``periodic`` (time, output); attrs ``omega`` (rad/s), ``model``,
``transient_file_text`` (the file it was made from) and the cache fingerprint
(:mod:`periodyn.studies.cache`).
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import xarray as xr

from . import cache
from .checks import FIXED_UNITS, Checker, FileSpec
from ..errors import InputError

__all__ = ["TransientSpec", "parse_transient", "run_transient"]

_KEYS = ("omega", "harmonics", "periods", "points", "samples", "rtol", "atol")


@dataclass(frozen=True)
class TransientSpec(FileSpec):
    """A validated transient study: omega (rad/s), harmonics of the periodic part (rheo-
    linear models), time span in periods, points, builder samples or None, integration
    tolerances (rtol, atol) of a DAE."""

    omega: float
    harmonics: int | None
    periods: float
    points: int
    samples: int | None
    tolerances: tuple[float, float]

    @property
    def kind(self) -> str:
        """"transient" (a SweepSpec says "sweep", a StudySpec "continuation")."""
        return "transient"

    @property
    def times(self) -> np.ndarray:
        """Equally spaced times from 0 over ``periods`` periods, (points,) s."""
        return np.linspace(0.0, self.periods * 2.0 * np.pi / self.omega, self.points)

    def build(self):
        """The model from [model.parameters] (and [transient] samples); builder errors
        become InputError naming the file."""
        kwargs = dict(self.parameters)
        if self.samples is not None:
            kwargs["samples"] = self.samples
        try:
            return self.builder(**kwargs)
        except (TypeError, ValueError, ArithmeticError, InputError) as exc:
            raise InputError(f"{self.source}: [model] {self.example} cannot be built from these parameters "
                             f"({type(exc).__name__}: {exc}); check [model.parameters] and [transient]") from None


def parse_transient(check: Checker, table, *, source, name, text, description, example, builder,
                    parameters) -> TransientSpec:
    """Validate a [transient] table (``check`` names the file)."""
    c = check.table(table, "[transient]")
    check.keys(c, "[transient]", _KEYS, ("omega",))
    om = check.table(c["omega"], "[transient] omega")
    check.keys(om, "[transient] omega", ("value", "unit"), ("value", "unit"))
    unit = check.string(om["unit"], "[transient] omega.unit")
    if unit not in FIXED_UNITS:
        check.fail("[transient] omega.unit", f"unknown unit '{unit}'; use one of: {', '.join(FIXED_UNITS)}")
    omega = check.number(om["value"], "[transient] omega.value", positive=True) * FIXED_UNITS[unit]
    harmonics = check.integer(c["harmonics"], "[transient] harmonics", 1) if "harmonics" in c else None
    periods = check.number(c.get("periods", 1.0), "[transient] periods", positive=True)
    points = check.integer(c.get("points", 401), "[transient] points", 2)
    if points > 100_000:
        check.fail("[transient] points", f"{points} points is more than a figure needs; at most 100000")
    samples = check.integer(c["samples"], "[transient] samples", 1) if "samples" in c else None
    tolerances = tuple(check.number(c.get(k, v), f"[transient] {k}", positive=True)
                       for k, v in (("rtol", 1e-9), ("atol", 1e-11)))
    return TransientSpec(source, name, text, description, example, builder, parameters, omega, harmonics, periods,
                         points, samples, tolerances)


def run_transient(spec: TransientSpec, out, *, resume: bool = False, **_unused) -> xr.Dataset:
    """Compute the transient of ``spec`` and write it to ``out`` (atomically) -> Dataset;
    with ``resume`` a current ``out`` is read and one made otherwise refused."""
    from ..dae import DAE
    from ..results import load, package_versions, save
    from ..system import OmegaSplitModel

    if cache.finished(out, spec, None, resume):
        return load(out)

    model = spec.build()
    t = spec.times
    variables = {}
    if isinstance(model, OmegaSplitModel):
        from ..harmonic.balance import periodic_solution
        from ..averaging import transient

        if spec.harmonics is None:
            raise InputError(f"{spec.source}: [transient]: {spec.example} is rheo-linear; give harmonics = <m> "
                             "for its periodic solution")
        system = model.at(spec.omega)
        periodic = periodic_solution(system, spec.harmonics)
        y0 = np.zeros(2 * system.n)
        methods = ("averaging", "integrate")
        runs = [transient(system, periodic, y0, t, method=m) for m in methods]
        outputs, names = np.stack([r.outputs for r in runs]), system.output_names
        variables["periodic"] = (("time", "output"), runs[0].periodic_outputs)
    elif isinstance(model, DAE):
        from ..nonlinear import element_outputs
        from ..numerics.integration import integrate

        rtol, atol = spec.tolerances
        q0 = np.asarray(getattr(model, "q0", None) if getattr(model, "q0", None) is not None else np.zeros(model.n),
                        dtype=float)
        q = integrate(model, spec.omega, (0.0, t[-1]), q0, np.zeros(model.n), t_eval=t, rtol=rtol, atol=atol).q
        elements = getattr(getattr(model, "equations", None), "model", None)
        methods = ("integrate",)
        if elements is not None:
            outputs, names = element_outputs(elements, spec.omega, t, q)[None], elements.output_names
        else:
            outputs, names = q[None], model.coordinate_names
    else:
        raise InputError(f"{spec.source}: [model] {spec.example} builds a {type(model).__name__}; a transient "
                         "study needs a rheo-linear example (OmegaSplitModel) or a DAE")
    variables["outputs"] = (("method", "time", "output"), outputs)
    ds = xr.Dataset(variables, coords={"time": t, "method": list(methods), "output": list(names)},
                    attrs={"model": spec.example, "omega": spec.omega, "description": spec.description,
                           "transient_file_text": spec.text, "versions": json.dumps(package_versions()),
                           **cache.stamp(spec)})
    save(ds, out)
    return ds
