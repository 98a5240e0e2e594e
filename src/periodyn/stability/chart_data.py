"""Two-parameter stability charts, the data: the options of a chart (:class:`ChartOptions`),
its boundary curves (:class:`ChartBoundary`), the chart (:class:`StabilityChart`) and the
monodromy checks of its points (:class:`ChartCheck`), and their self-describing dataset
(:func:`chart_dataset`, read back by :func:`chart_from_dataset`), saved by
:func:`periodyn.results.save`. The computation is :mod:`periodyn.stability.charts`.

Dataset layout: all boundary points along the dimension ``point``: ``parameter`` (p),
``omega`` (rad/s), ``kind`` (fold | period-doubling | neimark-sacker), ``side`` (+1 stable
just above omega, -1 just below, 0 a tip) and ``curve`` (which boundary, 0..B-1);
per boundary (dimension ``boundary``) ``start``/``stop``: how its ends stop; coordinates
``parameter_grid`` (P,) and ``omega_grid`` (S,) rad/s; with monodromy checks, along
``check``: ``check_curve``, ``check_parameter``, ``check_omega`` (rad/s), ``check_step``
(relative), ``check_max_real_outside``/``check_max_real_inside`` (1/s), ``check_kind``
(the type the monodromy gives inside) and ``check_agrees``. Attributes: ``parameter_name``,
the options, ``seeds``, ``evaluations``, ``builds``.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass

import numpy as np
import xarray as xr

from ..errors import InputError
from .boundaries import BoundaryCheck, StabilityBoundary
from .methods import check_method

__all__ = ["ChartOptions", "ChartBoundary", "StabilityChart", "ChartCheck", "chart_dataset", "chart_from_dataset",
           "checks_from_dataset"]


@dataclass(frozen=True)
class ChartOptions:
    """harmonics: m of Hill's method; method: a stability method
    (:mod:`periodyn.stability.methods`); xtol: relative tolerance in omega of every boundary
    point; ptol: tolerance of a tip in p, relative to the parameter range; max_halvings:
    halvings of a parameter step before a curve ends "lost"; truncation: "refuse" or "warn"
    (Hill results above the truncation tolerance)."""

    harmonics: int
    method: str = "auto"
    xtol: float = 1e-9
    ptol: float = 1e-7
    max_halvings: int = 6
    truncation: str = "refuse"

    def __post_init__(self):
        if isinstance(self.harmonics, bool) or not isinstance(self.harmonics, int) or self.harmonics < 1:
            raise InputError(f"harmonics must be an integer >= 1, got {self.harmonics!r}")
        check_method(self.method)
        for name in ("xtol", "ptol"):
            if not 0 < getattr(self, name) < 1e-2:
                raise InputError(f"{name} must be in (0, 1e-2), got {getattr(self, name)!r}")
        if not isinstance(self.max_halvings, int) or not 0 <= self.max_halvings <= 20:
            raise InputError(f"max_halvings must be an integer in [0, 20], got {self.max_halvings!r}")
        if self.truncation not in ("refuse", "warn"):
            raise InputError(f"truncation must be 'refuse' or 'warn', got {self.truncation!r}")


@dataclass(frozen=True, eq=False)
class ChartBoundary:
    """One boundary curve, k points in the order followed. parameter (k,) p; omega (k,)
    rad/s; kind (k,) str: fold | period-doubling | neimark-sacker; side (k,) int: +1 stable
    just above omega, -1 stable just below, 0 a tip (where the curve turns in p and joins the
    boundaries of a closing zone or gap); ends: how each end stops: "range" (the parameter
    grid's end), "omega" (it left the speed window), "loop" (a closed curve) or "lost: why"."""

    parameter: np.ndarray
    omega: np.ndarray
    kind: np.ndarray
    side: np.ndarray
    ends: tuple[str, str]

    @property
    def tips(self) -> np.ndarray:
        """Indices of the tips along the curve."""
        return np.flatnonzero(self.side == 0)


@dataclass(frozen=True, eq=False)
class StabilityChart:
    """The boundaries of a chart over ``parameter_grid`` (P,) and the speed window of
    ``omega_grid`` (S,) rad/s (the seeds' bisection grid), seeded at ``seeds``; options as
    given; evaluations and builds: exponent evaluations and models built."""

    parameter_name: str
    parameter_grid: np.ndarray
    omega_grid: np.ndarray
    seeds: tuple[float, ...]
    boundaries: tuple[ChartBoundary, ...]
    options: ChartOptions
    evaluations: int = 0
    builds: int = 0

    def at(self, p: float) -> list[tuple[float, str, int]]:
        """(omega rad/s, kind, side) of every boundary point at parameter value p (a grid
        value or a tip), by increasing omega."""
        rows = [(float(w), str(k), int(s)) for b in self.boundaries
                for q, w, k, s in zip(b.parameter, b.omega, b.kind, b.side) if q == p]
        return sorted(rows)


@dataclass(frozen=True)
class ChartCheck:
    """A boundary point of a chart checked by the monodromy matrix: boundary index,
    parameter value, the check (:class:`periodyn.stability.boundaries.BoundaryCheck`)."""

    boundary: int
    parameter: float
    check: BoundaryCheck


def chart_dataset(chart: StabilityChart, checks: tuple[ChartCheck, ...] = ()) -> xr.Dataset:
    """The self-describing dataset of ``chart`` (module docstring), with ``checks``."""
    b = chart.boundaries
    cat = (lambda name, dtype=float: np.concatenate([getattr(c, name) for c in b]).astype(dtype) if b
           else np.empty(0, dtype))
    ds = xr.Dataset(
        {"parameter": ("point", cat("parameter"), {"long_name": chart.parameter_name}),
         "omega": ("point", cat("omega"), {"units": "rad/s"}),
         "kind": ("point", cat("kind", object)),
         "side": ("point", cat("side", np.int8), {"description": "+1 stable just above omega, -1 just below, 0 tip"}),
         "curve": ("point", np.concatenate([np.full(c.omega.size, i) for i, c in enumerate(b)]) if b
                   else np.empty(0, int)),
         "start": ("boundary", np.array([c.ends[0] for c in b], dtype=object)),
         "stop": ("boundary", np.array([c.ends[1] for c in b], dtype=object))},
        coords={"parameter_grid": chart.parameter_grid, "omega_grid": ("omega_grid", chart.omega_grid,
                                                                       {"units": "rad/s"})},
        attrs={"parameter_name": chart.parameter_name, "options": json.dumps(asdict(chart.options)),
               "seeds": json.dumps(list(chart.seeds)), "evaluations": chart.evaluations, "builds": chart.builds})
    checked = [(c.boundary, c.parameter, c.check) for c in checks]
    columns = {"check_curve": [i for i, _, _ in checked], "check_parameter": [p for _, p, _ in checked],
               "check_omega": [c.boundary.omega for _, _, c in checked], "check_step": [c.step for _, _, c in checked],
               "check_max_real_outside": [c.max_real_outside for _, _, c in checked],
               "check_max_real_inside": [c.max_real_inside for _, _, c in checked],
               "check_kind": np.array([c.kind_inside for _, _, c in checked], dtype=object),
               "check_agrees": np.array([c.agrees for _, _, c in checked], dtype=bool)}
    return ds.assign({k: ("check", np.asarray(v)) for k, v in columns.items()})


def chart_from_dataset(ds: xr.Dataset) -> StabilityChart:
    """The chart a :func:`chart_dataset` holds."""
    if "curve" not in ds or "parameter_name" not in ds.attrs:
        raise InputError("this dataset is not a stability chart (no 'curve' variable or 'parameter_name' attribute); "
                         "read a result of a [chart] study")
    curve = ds["curve"].values
    boundaries = tuple(ChartBoundary(ds["parameter"].values[curve == i], ds["omega"].values[curve == i],
                                     ds["kind"].values[curve == i].astype(object), ds["side"].values[curve == i],
                                     (str(ds["start"].values[i]), str(ds["stop"].values[i])))
                       for i in range(ds.sizes["boundary"]))
    return StabilityChart(str(ds.attrs["parameter_name"]), ds["parameter_grid"].values, ds["omega_grid"].values,
                          tuple(json.loads(ds.attrs["seeds"])), boundaries,
                          ChartOptions(**json.loads(ds.attrs["options"])), int(ds.attrs["evaluations"]),
                          int(ds.attrs["builds"]))


def checks_from_dataset(ds: xr.Dataset) -> tuple[ChartCheck, ...]:
    """The monodromy checks a :func:`chart_dataset` holds."""
    out = []
    for i in range(ds.sizes.get("check", 0)):
        row = {k: ds[f"check_{k}"].values[i] for k in ("curve", "parameter", "omega", "step", "max_real_outside",
                                                         "max_real_inside", "kind")}
        curve = int(row["curve"])
        kinds = ds["kind"].values[(ds["curve"].values == curve) & (ds["omega"].values == row["omega"])]
        sides = ds["side"].values[(ds["curve"].values == curve) & (ds["omega"].values == row["omega"])]
        boundary = StabilityBoundary(float(row["omega"]), str(kinds[0]), bool(sides[0] > 0))
        out.append(ChartCheck(curve, float(row["parameter"]),
                              BoundaryCheck(boundary, float(row["step"]), float(row["max_real_outside"]),
                                            float(row["max_real_inside"]), str(row["kind"]))))
    return tuple(out)
