"""What a continuation study stores beside its branches so that figures only read:
the check of one orbit against direct integration (``time_history``) and the outputs of
an element model along every orbit of a branch (``output_samples``).

``time_history`` (a table of ``[continuation]``)::

    time_history = { omega = 3.6, branch = "frequency", start = "orbit", samples = 40 }

omega (in omega.unit): the branch point nearest to it (on the period-doubled branch
within its first pass, :func:`first_pass`; start "steady_state": exactly it); branch: "frequency" (default) or "period_doubled"; samples: integration times over
one orbit period, both ends included (default 40); rtol, atol: of the integration
(default 1e-10, 1e-12). start, the state the integration starts from at t = 0:

- "orbit" (default): the harmonic-balance orbit's own state;
- "shooting": the orbit re-solved by shooting (DOP853, its subharmonic) from it;
- "steady_state": the state that integration from the DAE's reference at rest settles
  to (change per period <= 1e-8, at most 3000 periods); the orbit is then EGA-IHB with
  the study's harmonics at omega started from that state, not a branch point (the
  attracting orbit where a branch has several).

The result's group "time_history" holds the orbit (``orbit_q``, ``orbit_lambda`` over
``orbit_time``, 401 times) and the integrated motion (``q``, ``lambda`` over ``time``),
with attributes omega (rad/s), period (s), branch, start, orbit_method, orbit_residual
(the orbit's Newton residual) and deviation (max |q - orbit q| over ``time``).

``output_samples = 64`` (element models only): each branch group gets ``outputs``
(point, sample, output), the model's non-linear outputs (``element_outputs``) along every
orbit at ``sample`` times s T / samples, measured from the rigid motion as the
linearized outputs are.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

__all__ = ["check_time_history", "orbit_time_history", "branch_outputs", "element_model_of", "rejoining_points",
           "first_pass"]

_STARTS = ("orbit", "shooting", "steady_state")
_BRANCHES = ("frequency", "period_doubled")
_KEYS = ("omega", "branch", "start", "samples", "rtol", "atol")
_ORBIT_TIMES = 401


def check_time_history(check, c: dict, speed) -> dict | None:
    """The validated ``time_history`` table of a [continuation] table ``c`` (None without
    one); the old key ``time_history_omega = w`` reads as ``time_history = { omega = w }``.
    speed: the checker of one speed in the file's unit."""
    import warnings

    where = "[continuation] time_history"
    if "time_history_omega" in c:
        if "time_history" in c:
            check.fail("[continuation] time_history_omega", "give time_history = { omega = ... } alone (the key "
                                                            "time_history_omega is its old form)")
        warnings.warn(f"{check.source}: [continuation] time_history_omega = w is the old form of time_history = "
                      "{ omega = w } (the study now computes the time history); the old key goes in the next release",
                      DeprecationWarning, stacklevel=4)
        return {"omega": speed(c["time_history_omega"], "[continuation] time_history_omega"), "branch": "frequency",
                "start": "orbit", "samples": 40, "rtol": 1e-10, "atol": 1e-12}
    if "time_history" not in c:
        return None
    table = check.table(c["time_history"], where)
    check.keys(table, where, _KEYS, ("omega",))
    out = {"omega": speed(table["omega"], f"{where}.omega")}
    for key, choices, default in (("branch", _BRANCHES, "frequency"), ("start", _STARTS, "orbit")):
        value = check.string(table.get(key, default), f"{where}.{key}")
        if value not in choices:
            check.fail(f"{where}.{key}", f"unknown {key} '{value}'; choose one of: {', '.join(choices)}")
        out[key] = value
    out["samples"] = check.integer(table.get("samples", 40), f"{where}.samples", 2)
    for key, default in (("rtol", 1e-10), ("atol", 1e-12)):
        out[key] = check.number(table.get(key, default), f"{where}.{key}", positive=True)
    return out


def orbit_time_history(system, branches: dict, request: dict, omega: float, harmonics: int) -> xr.Dataset:
    """The "time_history" group (module docstring) of ``request`` (a validated table) at
    ``omega`` (rad/s) for the DAE ``system`` and its computed branches {name: Branch}."""
    from ..errors import InputError
    from ..nonlinear import ihb, shooting
    from ..numerics.integration import integrate, steady_state

    if request["start"] == "steady_state":
        q, qd, _, _ = steady_state(system, omega, tol=1e-8, max_periods=3000)
        orbit = ihb(system, omega, harmonics, initial=q)
        branch_name = ""
    else:
        branch_name = request["branch"]
        if branch_name not in branches:
            raise InputError(f"time_history: the study has no {branch_name} branch (it has "
                             f"{', '.join(branches)}); choose branch = \"frequency\"")
        branch = branches[branch_name]
        end = first_pass(branch, branches["frequency"]) if branch_name == "period_doubled" else len(branch.omega)
        orbit = branch.solutions[int(np.argmin(np.abs(branch.omega[:end] - omega)))]
        start = orbit
        if request["start"] == "shooting":
            start = shooting(system, orbit.omega, initial=orbit, subharmonic=int(orbit.subharmonic))
        q, qd = start(0.0)[0], start.velocity(0.0)[0]
    T = orbit.period
    t = np.linspace(0.0, T, request["samples"])
    th = integrate(system, orbit.omega, (0.0, T), q, qd, t_eval=t, rtol=request["rtol"], atol=request["atol"])
    dense = np.linspace(0.0, T, _ORBIT_TIMES)
    length = "m or rad (the coordinate's)"
    force = "N or N m (the multiplier's)"
    return xr.Dataset(
        {"orbit_q": (("orbit_time", "coordinate"), orbit(dense), {"units": length}),
         "orbit_lambda": (("orbit_time", "constraint"), orbit.lam(dense), {"units": force}),
         "q": (("time", "coordinate"), th.q, {"units": length}),
         "lambda": (("time", "constraint"), th.lam, {"units": force})},
        coords={"time": ("time", th.t, {"units": "s"}), "orbit_time": ("orbit_time", dense, {"units": "s"}),
                "coordinate": list(orbit.coordinate_names), "constraint": list(orbit.constraint_names)},
        attrs={"omega": float(orbit.omega), "period": float(T), "branch": branch_name, "start": request["start"],
               "orbit_method": orbit.method, "orbit_residual": float(orbit.residual),
               "deviation": float(np.max(np.abs(th.q - orbit(th.t)))),
               "description": "orbit (lines) against the motion integrated from the start state over one period"})


def rejoining_points(branch, parent, rtol: float = 1e-6) -> list:
    """The special points of a period-doubled ``branch`` (past its first point) that lie
    at a period-doubling point of ``parent``, the period-1 branch it was switched from
    (omega within ``rtol``): where it rejoins ``parent``."""
    doublings = [p.omega for p in parent.points("period-doubling")]
    return [p for p in branch.special_points
            if p.index > 0 and any(abs(p.omega - w) <= rtol * max(abs(p.omega), abs(w)) for w in doublings)]


def first_pass(branch, parent, rtol: float = 1e-6) -> int:
    """Number of points of a period-doubled ``branch`` up to where it first rejoins
    ``parent`` (:func:`rejoining_points`; all points when it does not): beyond, the
    continuation retraces it as the orbits shifted by one period T."""
    at_parent = rejoining_points(branch, parent, rtol)
    return min(p.index for p in at_parent) + 2 if at_parent else len(branch.omega)


def element_model_of(system):
    """The element model behind a DAE built from one (None for other DAEs)."""
    equations = getattr(system, "equations", None)
    return getattr(equations, "model", None) if hasattr(equations, "configurations") else None


def branch_outputs(model, branch, samples: int) -> xr.Dataset:
    """``outputs`` (point, sample, output) of the element ``model`` along every orbit of
    ``branch`` at times s T / samples, with its coordinates ``output`` and
    ``output_units`` (merged into the branch's group)."""
    from ..nonlinear import element_outputs

    values = np.empty((len(branch.omega), samples, len(model.outputs)))
    for k, orbit in enumerate(branch.solutions):
        t = np.arange(samples) * orbit.period / samples
        values[k] = element_outputs(model, orbit.omega, t, orbit(t))
    units = [{"midpoint_deflection": "1", "relative_rotation": "rad"}.get(o.kind, f"1/{o.scale:g} of the coordinate")
             for o in model.outputs]
    attrs = {"units": "per output: output_units", "samples_per_period": samples,
             "description": "outputs along each orbit at t = sample T / samples_per_period, minus their value on the "
                            "rigid motion"}
    return xr.Dataset({"outputs": (("point", "sample", "output"), values, attrs)},
                      coords={"output": list(model.output_names), "output_units": ("output", units),
                              "sample": np.arange(samples)})
