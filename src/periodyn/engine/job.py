"""The job a sweep sends to its workers: the model source (one system per grid point
and speed) and the solve of a chunk of flat point indices into result columns.

The model the parent built for the first grid point travels with its omega-polynomial
spectra already computed; other grid points are built once per worker, never per speed.
A point whose solver raises :class:`~periodyn.errors.ConvergenceError`, or whose result
holds any non-finite number, is kept as a failed point (NaN, ``status = 1``, ``message``
saying why), never as a result.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from ..speeds import SpeedBatch, SpeedSolver, solve_point
from ..errors import ConvergenceError, InputError
from ..results import STABILITY_RECORDS, STATUS_SOLVED, empty_columns
from ..system import OmegaSplitModel, RheoLinear

__all__ = ["ModelSource", "Job", "reference_frequencies", "describe"]


class ModelSource:
    """Gives the system at one grid point. ``model`` is an OmegaSplitModel or a callable
    omega -> RheoLinear; with a parameter grid it is a builder called with the grid
    point's keyword values, returning either. Built models (with their cached spectra)
    are kept and travel with the job, so workers build only grid points not built yet."""

    def __init__(self, model, grid_names: tuple[str, ...], grid_values: tuple[np.ndarray, ...],
                 samples: int | None):
        self.model = model
        self.grid_names = grid_names
        self.grid_values = grid_values
        self.samples = samples
        self._built: dict[tuple[int, ...], Any] = {}

    def parameters(self, index: tuple[int, ...]) -> dict[str, Any]:
        """Grid point ``index`` as builder keyword values."""
        return {name: _python_scalar(values[i]) for name, values, i in zip(self.grid_names, self.grid_values, index)}

    def model_at(self, index: tuple[int, ...]):
        built = self._built.get(index)
        if built is None:
            if self.grid_names:
                params = self.parameters(index)
                try:
                    built = self.model(**params)
                except InputError as exc:
                    raise InputError(f"model builder with {describe(params)}: {exc}") from None
                except TypeError as exc:
                    raise InputError(f"model builder does not accept {describe(params)} ({exc}); "
                                     "grid parameters must be keyword arguments of the builder") from None
            else:
                built = self.model
            if isinstance(built, OmegaSplitModel):
                if self.samples is not None:
                    built = built.with_samples(self.samples)
            elif not callable(built):
                raise InputError(f"a model must be a periodyn.OmegaSplitModel or a callable omega -> RheoLinear, "
                                 f"got {type(built).__name__}")
            self._built[index] = built
        return built

    def system(self, index: tuple[int, ...], omega: float) -> RheoLinear:
        model = self.model_at(index)
        system = model.at(omega) if isinstance(model, OmegaSplitModel) else model(omega)
        if not isinstance(system, RheoLinear):
            raise InputError(f"the model callable returned {type(system).__name__} at omega = {omega:.6g} rad/s; "
                             "it must return a periodyn.RheoLinear")
        if self.samples is not None and system.samples != self.samples:
            raise InputError(f"samples = {self.samples} was asked for but the model callable gives systems with "
                             f"{system.samples} samples; drop samples or build the systems with {self.samples}")
        return system


def _python_scalar(value):
    return value.item() if isinstance(value, np.generic) else value


def describe(params: Mapping[str, Any]) -> str:
    return ", ".join(f"{k} = {v!r}" for k, v in params.items()) or "no parameters"


# ----------------------------------------------------------------------------- job
_CALLABLE_SECONDS = 1e-2  # nominal seconds per speed of a callable model (a system built and solved per speed)


@dataclass
class Job:
    """Everything a worker needs; sent once per worker. Points have flat indices
    into ``shape = (*grid, n_omega)``."""

    source: ModelSource
    omega: np.ndarray
    harmonics: int
    stability: bool
    method: str
    n_outputs: int
    n_exponents: int
    _solvers: dict = field(default_factory=dict, repr=False)  # per grid point, built where used
    speed_cost: np.ndarray | None = None  # estimated seconds per speed (speed_costs), where set
    writer: Any = None  # on local workers: the Checkpoint they write their chunks to
    streamed: bool = False  # with writer: the workers send back receipts (stream.receipt), not the chunks

    def point_costs(self, indices: np.ndarray) -> np.ndarray:
        """Estimated seconds of the points with these flat indices: ``speed_cost`` of
        their speeds, else 1 each."""
        if self.speed_cost is None:
            return np.ones(len(indices))
        return self.speed_cost[np.asarray(indices) % len(self.omega)]

    def __getstate__(self):
        state = dict(self.__dict__)
        state["_solvers"] = {}  # speed solvers are rebuilt in each worker, never shipped
        return state

    def speed_costs(self) -> np.ndarray:
        """Estimated seconds (n_omega,) of each speed at the first grid point, for sharing
        the work out (:meth:`periodyn.speeds.SpeedSolver.speed_costs`; every grid point
        is taken to cost alike); the same at every speed for a callable model
        (_CALLABLE_SECONDS: it builds and solves its system at each speed)."""
        first = (0,) * len(self.source.grid_names)
        if not isinstance(self.source.model_at(first), OmegaSplitModel):
            return np.full(len(self.omega), _CALLABLE_SECONDS)
        return self._solver(first).speed_costs(self.omega)

    def _solver(self, grid_index: tuple[int, ...]) -> SpeedSolver:
        solver = self._solvers.get(grid_index)
        if solver is None:
            model = self.source.model_at(grid_index)
            stability = self.method if self.stability else False
            solver = self._solvers[grid_index] = SpeedSolver(model, self.harmonics, stability)
        return solver

    def batch(self, grid_index: tuple[int, ...], omegas: np.ndarray) -> SpeedBatch:
        """Results at one grid point for the speeds omegas: an OmegaSplitModel goes through
        its SpeedSolver (omega-polynomial blocks built once per model, chunks of speeds at
        once), a callable model point by point through solve_point."""
        model = self.source.model_at(grid_index)
        if isinstance(model, OmegaSplitModel):
            return self._solver(grid_index).solve_many(omegas)
        points, messages = [], []
        for w in omegas:
            try:
                points.append(solve_point(self.source.system(grid_index, w), self.harmonics,
                                          stability=self.method if self.stability else False))
                messages.append("")
            except ConvergenceError as exc:
                points.append(None)
                messages.append(str(exc) or type(exc).__name__)
            except InputError as exc:
                raise InputError(f"at omega = {w:.6g} rad/s: {exc}") from None
        return SpeedBatch.from_points(omegas, points, messages)

    def coordinates(self, indices: np.ndarray) -> dict[str, np.ndarray]:
        """Where the points with these flat indices lie: ``omega`` (rad/s) and the value of
        each grid parameter, one entry per point (stored with each checkpoint chunk)."""
        located = np.unravel_index(np.asarray(indices, dtype=np.int64), self.shape)
        coords = {"omega": self.omega[located[-1]]}
        for name, values, at in zip(self.source.grid_names, self.source.grid_values, located[:-1]):
            values = np.asarray(values)
            coords[name] = (values if values.dtype.kind in "biufcUS" else values.astype(str))[at]
        return coords

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.source.grid_values) + (len(self.omega),)

    def empty(self, count: int) -> dict[str, np.ndarray]:
        """Result columns for ``count`` points (see :func:`periodyn.results.empty_columns`)."""
        return empty_columns(count, self.harmonics, self.n_outputs, self.n_exponents)

    def solve(self, indices: np.ndarray) -> dict[str, np.ndarray]:
        """Solve the points with these flat indices; returns chunk arrays (see :meth:`empty`)."""
        out = self.empty(len(indices))
        out["index"][:] = indices
        located = np.unravel_index(indices, self.shape)
        with np.errstate(all="ignore"):  # overflow becomes a failed point with its reason (below)
            self._solve_into(out, located)
        out["message"] = out["message"].astype(str)
        out["stability_method"] = out["stability_method"].astype(str)
        return out

    def _solve_into(self, out: dict[str, np.ndarray], located: tuple[np.ndarray, ...]) -> None:
        indices = out["index"]
        if len(located) == 1:  # no parameter grid: one model
            self._solve_rows(out, (), np.arange(len(indices)), located[0])
            return
        grid = np.stack(located[:-1], axis=1)
        for key in np.unique(grid, axis=0):
            rows = np.nonzero((grid == key).all(axis=1))[0]
            self._solve_rows(out, tuple(int(k) for k in key), rows, located[-1][rows])

    def _solve_rows(self, out: dict[str, np.ndarray], grid_index: tuple[int, ...], rows: np.ndarray,
                    speeds: np.ndarray) -> None:
        """Points ``rows`` of ``out``: speeds (indices into omega) at one grid point, solved
        together; a ConvergenceError (or an arithmetic or LAPACK breakdown) of the batch is
        retried speed by speed, so that it fails only the speeds it belongs to."""
        try:
            batch = self.batch(grid_index, self.omega[speeds])
        except InputError as exc:
            if not self.source.grid_names:
                raise
            raise InputError(f"{exc} ({describe(self.source.parameters(grid_index))})") from None
        except (ConvergenceError, ArithmeticError, np.linalg.LinAlgError) as exc:
            if len(rows) > 1:
                for row, speed in zip(rows, speeds):
                    self._solve_rows(out, grid_index, row[None], speed[None])
            elif isinstance(exc, ConvergenceError):
                out["message"][rows] = str(exc) or type(exc).__name__
            else:  # a numerical breakdown on overflowing or degenerate coefficients
                out["message"][rows] = (f"numerical failure ({type(exc).__name__}: {exc}) at omega = "
                                        f"{self.omega[speeds[0]]:.6g} rad/s; check the model parameters "
                                        "(sizes, units)")
            return
        if (batch.output_harmonics.shape[1:] != out["harmonics"].shape[1:]
                or batch.exponents.shape[1:] != (self.n_exponents,)):
            raise InputError(f"the model at {describe(self.source.parameters(grid_index))} has "
                             "other outputs or coordinates than at the first point; every grid point must have "
                             "the same outputs and coordinates")
        solved = batch.message == ""
        nonfinite = _nonfinite(batch, self.stability)
        nonfinite[~solved] = ""  # a failed point keeps the reason it failed
        out["message"][rows] = np.where(nonfinite != "", nonfinite, batch.message)
        solved &= nonfinite == ""
        for name, column in (("amplitude", batch.amplitude), ("mean", batch.mean),
                             ("harmonics", batch.output_harmonics), ("residual", batch.residual),
                             ("max_real_exponent", batch.max_real), ("exponents", batch.exponents),
                             ("multipliers", batch.multipliers), ("stable", batch.stable),
                             ("stability_method", batch.method),
                             *((name, getattr(batch, name)) for name in STABILITY_RECORDS)):
            out[name][rows[solved]] = column[solved]
        out["status"][rows[solved]] = STATUS_SOLVED


_CHECKED = ("amplitude", "mean", "output_harmonics", "residual")
_CHECKED_STABILITY = ("exponents", "multipliers", "max_real")


def _nonfinite(batch: SpeedBatch, stability: bool) -> np.ndarray:
    """Per speed of ``batch``: '' where every number of the result is finite, else the
    reason naming the quantities that are not (the point is then a failed point)."""
    names = _CHECKED + (_CHECKED_STABILITY if stability else ())
    bad = {name: ~np.isfinite(getattr(batch, name)).reshape(len(batch), -1).any(axis=1) for name in names}
    reasons = np.full(len(batch), "", dtype=object)
    for i in np.flatnonzero(np.any(list(bad.values()), axis=0)):
        which = ", ".join(name for name in names if bad[name][i])
        reasons[i] = (f"non-finite result ({which}) at omega = {batch.omega[i]:.6g} rad/s: the model's "
                      "coefficients or the solution overflow; check the model parameters (sizes, units)")
    return reasons



def reference_frequencies(model) -> dict[str, float]:
    """Reference frequencies (rad/s) of a model: its ``metadata`` entries named omega*."""
    meta = getattr(model, "metadata", None)
    if not isinstance(meta, Mapping):
        return {}
    return {str(k): float(v) for k, v in meta.items()
            if str(k).startswith("omega") and isinstance(v, (int, float, np.number)) and not isinstance(v, bool)}

