"""One speed, everything a sweep records: periodic solution, output harmonics and
amplitudes, and (optionally) the characteristic exponents.

:func:`solve_point` works on any :class:`RheoLinear`. :class:`SpeedSolver` serves a
constant-speed :class:`OmegaSplitModel`: the Hill/HB blocks are polynomials in omega
(``W = sum_p w^p W_p`` up to p = 4, ``V`` up to 2, ``Mh`` constant), so their terms are
built once per model, and a chunk of speeds costs polynomial evaluations, stacked LAPACK
solves and eigen-solves, and jitted kernels (:class:`SpeedBatch` holds the columns).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .errors import ConvergenceError, InputError
from .stability.floquet import TRUNCATION_TOL, FloquetExponents, TruncationWarning, is_stable, truncation_message
from .harmonic.operator import HarmonicOperator, HillOperator, check_harmonics
from .harmonic.batch_balance import BalanceBatch
from .harmonic.balance import amplification, balance_failure, periodic_solution
from .harmonic.reduced_balance import ReducedBalance
from .harmonic.truncation import (BALANCE_TRUNCATION_TOL, BalanceTruncationWarning, SweepTruncation, BLOCK,
                                  balance_truncation_message)
from .stability.batch import SpeedStability
from .stability.methods import method_named, stability_choice
from .periodic import PeriodicSolution, half_range_and_mean, output_spectrum
from .results import STABILITY_RECORDS
from .system import OmegaSplitModel, RheoLinear
from .stability.magnus import half_period_signs
from .stability.reduced import AUTO_MIN_COORDINATES, START_MODES, reduced_pays
from .model.reduce import guarded_modes

__all__ = ["PointResult", "SpeedBatch", "solve_point", "SpeedSolver", "warm_up"]


@dataclass(frozen=True, eq=False)
class PointResult:
    """Results at one speed. omega rad/s; output_harmonics (2m+1, n_out) complex, l=-m..m;
    amplitude/mean (n_out,) half peak-to-peak and mean of the outputs; residual: relative
    HB residual; exponents/multipliers (2n,) complex (NaN without stability); max_real 1/s;
    stable (False also when stability was not computed); method: the stability method
    used ("" without stability; what "auto" chose) and reason: why."""

    omega: float
    output_names: tuple[str, ...]
    output_harmonics: np.ndarray
    amplitude: np.ndarray
    mean: np.ndarray
    residual: float
    exponents: np.ndarray
    multipliers: np.ndarray
    max_real: float
    stable: bool
    method: str = ""
    reason: str = ""


def _point(sol: PeriodicSolution, fl: FloquetExponents | None, n: int) -> PointResult:
    """PointResult from a periodic solution and its exponents (None without stability)."""
    if fl is not None:
        exps, mults, max_real, stable = fl.exponents, fl.multipliers, fl.max_real, fl.stable
        used, reason = fl.method, fl.reason
    else:
        exps = mults = np.full(2 * n, np.nan + 0j)
        max_real, stable, used, reason = float("nan"), False, "", ""
    return PointResult(sol.omega, sol.output_names, sol.output_harmonics, sol.output_amplitude(), sol.output_mean(),
                       sol.residual, exps, mults, max_real, stable, used, reason)


def solve_point(system: RheoLinear, harmonics: int, stability: bool | str = True, method: str | None = None, *,
                form: str = "direct") -> PointResult:
    """Harmonic balance and, with ``stability`` (True = "auto", False, or a stability method
    of :mod:`periodyn.stability.methods`), the characteristic exponents (as in
    :func:`periodyn.characteristic_exponents`) for one rheo-linear system. ``method=``:
    deprecated name of the stability method. A Hill verdict above the truncation tolerance
    raises ConvergenceError (increase harmonics)."""
    m = check_harmonics(harmonics)
    stability, method = stability_choice(stability, method, "solve_point")
    op = HarmonicOperator.for_system(system, m, form).at(system.omega)
    sol = periodic_solution(system, m, form=form, operator=op)
    fl = method_named(method).exponents(system, op) if stability else None
    if fl is not None and fl.truncation > TRUNCATION_TOL:  # as a sweep's failed point (SpeedSolver.solve)
        raise ConvergenceError(truncation_message(fl.truncation, m, fl.omega, fl.method))
    return _point(sol, fl, system.n)


@dataclass(frozen=True, eq=False)
class SpeedBatch:
    """Results at S speeds, columnar (the fields of :class:`PointResult` with a leading
    speed axis). message: (S,) str, empty where the point was solved, else why it failed
    (its stability entries are then NaN and ``stable`` False); method: (S,) str, the
    stability method used at each speed ("" without stability); reduced_modes,
    reduced_correction (1/s), stability_error_bound: (S,) what the method "reduced" records
    (:data:`periodyn.results.STABILITY_RECORDS`, their fill values where it did not certify);
    balance_modes: (S,) modes kept by the reduced HB (0 where the full HB solved the speed);
    balance_truncation: (S,) the HB truncation indicator (:mod:`periodyn.harmonic.truncation`);
    hill_truncation: (S,) Hill's truncation indicator (NaN where no Hill method judged the speed)."""

    omega: np.ndarray
    output_names: tuple[str, ...]
    output_harmonics: np.ndarray
    amplitude: np.ndarray
    mean: np.ndarray
    residual: np.ndarray
    exponents: np.ndarray
    multipliers: np.ndarray
    max_real: np.ndarray
    stable: np.ndarray
    message: np.ndarray
    method: np.ndarray
    reduced_modes: np.ndarray
    reduced_correction: np.ndarray
    stability_error_bound: np.ndarray
    balance_modes: np.ndarray
    balance_truncation: np.ndarray
    hill_truncation: np.ndarray

    def __len__(self) -> int:
        return self.omega.shape[0]

    @classmethod
    def from_points(cls, omegas: np.ndarray, points: list[PointResult | None], messages: list[str]) -> SpeedBatch:
        """Columns from per-speed results (None where the point failed, with its message);
        at least one point must have been solved."""
        ok = next((p for p in points if p is not None), None)
        if ok is None:
            raise ConvergenceError("no speed of the batch was solved: " + "; ".join(messages))
        filled = [p if p is not None else
                  PointResult(float(w), ok.output_names, np.full_like(ok.output_harmonics, np.nan),
                              np.full_like(ok.amplitude, np.nan), np.full_like(ok.mean, np.nan), float("nan"),
                              np.full_like(ok.exponents, np.nan), np.full_like(ok.multipliers, np.nan), float("nan"),
                              False) for w, p in zip(omegas, points)]
        return cls(np.asarray(omegas, float), ok.output_names,
                   *(np.stack([getattr(p, f) for p in filled]) for f in ("output_harmonics", "amplitude", "mean",
                                                                         "residual", "exponents", "multipliers",
                                                                         "max_real", "stable")),
                   np.asarray(messages, dtype=str), np.array([p.method if p is not None else "" for p in points],
                                                             dtype=str),
                   *(np.full(len(points), fill) for fill in STABILITY_RECORDS.values()))

    def point(self, i: int) -> PointResult:
        """The PointResult of speed i."""
        return PointResult(float(self.omega[i]), self.output_names, self.output_harmonics[i], self.amplitude[i],
                           self.mean[i], float(self.residual[i]), self.exponents[i], self.multipliers[i],
                           float(self.max_real[i]), bool(self.stable[i]), str(self.method[i]))


_BATCH_ELEMENTS = 4_000_000  # matrix entries per stacked LAPACK call (memory of a speed chunk)
# speed_costs (load balance of sweeps): HB multiply-adds per second and set-up per speed
# (Cardan shaft 0.1 ms, slider-crank 0.05 ms per speed measured on one core)
_HB_RATE, _HB_SETUP = 1e10, 5e-6
#: speeds at which a sweep's cost estimate is taken, at most (interpolated between them)
COST_SPEEDS = 128


class SpeedSolver:
    """Per-model precomputation for speed sweeps of an :class:`OmegaSplitModel`.

    The Hill/HB blocks are polynomials in omega; their terms, and where they pay off the
    terms of the real HB matrix and what the stability method keeps per model
    (:class:`periodyn.stability.batch.SpeedStability`), are built once. ``solve_many(omegas)``
    then treats a chunk of speeds with stacked LAPACK calls and jitted kernels; the
    large-system paths (banded/sparse HB, ARPACK Hill, DOP853 monodromy) go speed by speed.
    stability: True (= "auto"), False, or a stability method name; ``method=``: its
    deprecated name. With stability "reduced" (form "direct"), and "auto" on the chunks where
    it takes the method "reduced", the HB is the reduced one too
    (:mod:`periodyn.harmonic.reduced_balance`: the mean modes of the stability method, the
    residual of the full HB equations below its RTOL; a speed where it does not converge is
    solved in full), ``reduced_balance`` True. ``solve(omega)`` gives the same
    :class:`PointResult` as ``solve_point(model.at(omega), harmonics, stability, form=form)``.
    """

    def __init__(self, model: OmegaSplitModel, harmonics: int, stability: bool | str = True,
                 method: str | None = None, form: str = "direct"):
        self.model = model
        self.m = check_harmonics(harmonics)
        self.stability, self.method = stability_choice(stability, method, "SpeedSolver")
        self.form = form
        self.harmonic = op = HarmonicOperator.for_model(model, self.m, form)
        self.output_spectra = model._power_spectra[4]
        self.pattern = op.pattern
        # HB per chunk of speeds: jitted banded LU for narrow small bands; stacked real dense
        # LAPACK (in half-period symmetry classes) for small systems whose band is wide;
        # otherwise speed by speed
        self.balance = BalanceBatch(op, model.derived("half_period_signs", None,
                                                      lambda: half_period_signs(*model._power_spectra[:3])))
        self.storage, self.batch_balance = self.balance.storage, self.balance.kind
        self.speed_stability = SpeedStability(model, op, self.method)
        self.dense_hill = self.stability and self.speed_stability.dense_hill
        self.reduced_balance = self.stability and form == "direct" and (
            self.method == "reduced" or self.method == "auto" and model.n >= AUTO_MIN_COORDINATES)

    @property
    def ladder(self):
        """The model's certified Magnus ladder (:class:`periodyn.stability.magnus.MagnusLadder`)
        that the method "auto" climbs (built once, on first use)."""
        return self.speed_stability.prepared("auto")

    def operator(self, omega: float) -> HillOperator:
        """The Hill/HB operator at driving speed omega (rad/s)."""
        return self.harmonic.at(check_speeds(omega)[0], real_first_order=self.method == "dense" and self.dense_hill)

    def hill_methods(self, omegas) -> list[tuple[str, str, float]]:
        """Hill method at each speed (rad/s), why, and its estimated seconds: "auto"
        chooses per speed by estimated cost (:func:`periodyn.stability.methods.choose_method`),
        as the per-speed path does."""
        return self.speed_stability.hill_choices(check_speeds(omegas))

    def stability_methods(self, omegas) -> list[tuple[str, str]]:
        """Stability method at each speed (rad/s) and why (for "auto": Magnus where its
        error estimate certifies the verdict within Hill's estimated cost, else Hill)."""
        names, reasons = self.speed_stability.choose(check_speeds(omegas))[:2]
        return list(zip(names, reasons))

    def speed_costs(self, omegas) -> np.ndarray:
        """Estimated seconds (S,) of each speed (rad/s), for sharing a sweep's work out
        evenly and judging whether worker processes pay (a rough estimate: measured chunk
        times were 0.8-2.9x it on the Cardan shaft). The harmonic balance costs the same
        at every speed (its LU: the cheaper of N^3/3 dense and 2 N u^2 banded multiply-adds, at
        _HB_RATE, plus a set-up); the stability method adds its own estimate
        (``sweep_cost`` of its registry entry: "auto" its Magnus climb, "monodromy" its
        integration over one period; the others cost the same at every speed). Beyond
        COST_SPEEDS speeds the estimate is taken at COST_SPEEDS speeds spread evenly over their
        range and interpolated (it changes slowly with the speed; computed in the sweep's own
        process, it must not grow with the sweep)."""
        w = check_speeds(omegas)
        if w.size > COST_SPEEDS:
            grid = np.linspace(w.min(), w.max(), COST_SPEEDS)
            return np.interp(w, grid, self.speed_costs(grid))
        pat = self.pattern
        hb = _HB_SETUP + min(pat.size**3 / 3.0, 2.0 * pat.size * pat.half_bandwidth**2) / _HB_RATE
        if self.reduced_balance:  # about five residuals (P = band + 2m + 1 angles, 6 n^2 each) and the kept LU
            kept = (2 * self.m + 1) * min(START_MODES, self.model.n)
            residuals = 5 * 2 * (pat.band + 2 * self.m + 1) * 6 * self.model.n**2
            hb = min(hb, _HB_SETUP + (residuals + kept**3 / 3.0) / _HB_RATE)
        return self.speed_stability.costs(w, hb) if self.stability else np.full(w.size, hb)

    def solve(self, omega: float) -> PointResult:
        """Periodic solution and stability at one speed (rad/s); raises ConvergenceError
        when the harmonic balance or the stability analysis fails there."""
        batch = self.solve_many([omega])
        if batch.message[0]:
            raise ConvergenceError(str(batch.message[0]))
        return batch.point(0)

    def solve_many(self, omegas) -> SpeedBatch:
        """Periodic solutions and stability at the speeds omegas (S,) rad/s, in chunks whose
        stacked matrices stay below a few million entries."""
        w = check_speeds(omegas)
        N = self.pattern.size
        per_speed = max(4 * N * N if self.dense_hill else 0, N * N if self.batch_balance == "dense" else 0,
                        3 * N * self.pattern.half_bandwidth + N)
        if self.reduced_balance:  # its samples; dense Hill (a speed "reduced" hands on) takes sub-chunks
            per_speed = 16 * (self.pattern.band + 2 * self.m + 1) * self.model.n
        chunk = int(np.clip(_BATCH_ELEMENTS // per_speed, 1, 256))
        if self.reduced_balance and chunk > BLOCK:  # whole blocks of the truncation indicator's products
            chunk -= chunk % BLOCK
        parts = [self._solve_chunk(w[i: i + chunk]) for i in range(0, w.size, chunk)]
        if len(parts) == 1:
            return parts[0]
        return SpeedBatch(w, self.model.output_names,
                          *(np.concatenate([getattr(b, f) for b in parts]) for f in SpeedBatch.__dataclass_fields__
                            if f not in ("omega", "output_names")))

    def _balance(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Harmonics (S, 2m+1, n), relative HB residuals (S,), failure messages (S,) and the
        modes kept by the reduced HB (S,; 0 where solved in full) at speeds w (S,): the
        reduced HB where ``reduced_balance`` and the guarded mode count (START_MODES and the
        parametric reach at the chunk's highest speed) leaves modes out, else (and where it
        does not converge) the path ``batch_balance`` (:mod:`periodyn.harmonic.batch_balance`)."""
        modes = np.zeros(w.size, np.int32)
        k = self.model.n
        if self.reduced_balance and (self.method == "reduced" or reduced_pays(self.speed_stability, w).any()):
            reduced = self.model.derived("reduced_balance", (self.m, self.pattern.band), lambda: ReducedBalance(
                self.model, self.m, self.pattern.band, self.speed_stability.prepared("reduced").modes))
            k = guarded_modes(reduced.modes, min(START_MODES, self.model.n), self.m, float(w.max()))
        if k >= self.model.n:
            return (*self.balance.solve_many(w, self.batch_balance), modes)
        q, residual, steps = reduced.solve_many(w, k)
        message = np.full(w.size, "", dtype=object)
        ok = (steps > 0) & np.isfinite(q).reshape(w.size, -1).all(axis=1)
        amplified = amplification(reduced.row_scales(w), q.reshape(w.size, -1), reduced.forcing(w).reshape(w.size, -1))
        for i in np.flatnonzero(ok):
            message[i] = balance_failure(w[i], residual[i], amplified[i], f"reduced, {k} modes")
        modes[ok] = k
        full = np.flatnonzero(~ok)
        if full.size:
            q[full], residual[full], message[full] = self.balance.solve_many(w[full], self.batch_balance)
        q[message != ""] = 0.0
        return q, residual, message, modes

    def _solve_chunk(self, w: np.ndarray) -> SpeedBatch:
        q, residual, balance_message, balance_modes = self._balance(w)
        spectrum = output_spectrum(self.output_spectra, q)  # (S, 2M+1, n_out)
        S, H, n_out = spectrum.shape
        half, mean = half_range_and_mean(np.moveaxis(spectrum, 0, 1).reshape(H, S * n_out))
        M = (H - 1) // 2
        harmonics = spectrum[:, M - self.m: M + self.m + 1]
        if self.stability:
            finite = np.isfinite(q).reshape(S, -1).all(axis=1) & np.isfinite(half).reshape(S, -1).all(axis=1)
            exps, message, methods, records = self.speed_stability.solve(w, (balance_message == "") & finite)
            multipliers = np.exp(exps * (2 * np.pi / w)[:, None])
            max_real = exps.real.max(axis=1)
            stable = is_stable(max_real, 2 * np.pi / w)  # False where NaN (failed)
        else:
            exps = multipliers = np.full((S, 2 * self.model.n), np.nan + 0j)
            max_real, stable, message = np.full(S, np.nan), np.zeros(S, dtype=bool), np.full(S, "", dtype=object)
            methods = message
            records = {name: np.full(S, fill) for name, fill in STABILITY_RECORDS.items()}
        records["balance_modes"] = balance_modes
        records["balance_truncation"] = self._truncation(q, w)
        failed = balance_message != ""  # no periodic solution: the point fails with the HB's reason
        recorded = (np.where(failed, fill, records[name]) for name, fill in STABILITY_RECORDS.items())
        message = np.where(failed, balance_message, message)
        columns = (np.where(failed.reshape((S,) + (1,) * (a.ndim - 1)), np.nan, a)
                   for a in (harmonics, half.reshape(S, n_out), mean.reshape(S, n_out), residual, exps, multipliers,
                             max_real))
        return SpeedBatch(w, self.model.output_names, *columns, stable & ~failed, message.astype(str),
                          methods.astype(str), *recorded)


    def _truncation(self, q: np.ndarray, w: np.ndarray) -> np.ndarray:
        """HB truncation indicators (S,) of the harmonics q (S, 2m+1, n) at speeds w (S,);
        warns (BalanceTruncationWarning) where one is above BALANCE_TRUNCATION_TOL."""
        truncation = self.model.derived("sweep_truncation", self.m,
                                        lambda: SweepTruncation(self.model._power_spectra[:4], self.m))
        indicator = truncation(q, w)
        high = np.flatnonzero(indicator > BALANCE_TRUNCATION_TOL)
        if high.size:
            warnings.warn(f"{high.size} of {w.size} speeds: " + balance_truncation_message(
                indicator[high[0]], self.m, w[high[0]]), BalanceTruncationWarning, stacklevel=4)
        return indicator


def check_speeds(omegas) -> np.ndarray:
    """Driving speeds as a float array (S,) (one speed or a non-empty 1-D array), refusing
    non-positive or non-finite values with the offending entry named."""
    try:
        w = np.atleast_1d(np.asarray(omegas, dtype=float))
    except (TypeError, ValueError):
        raise InputError(f"omega must be driving speeds in rad/s (numbers), got {type(omegas).__name__}") from None
    if w.ndim != 1 or w.size == 0:
        raise InputError(f"omega must be one speed or a non-empty 1-D array of speeds in rad/s, got shape {w.shape}")
    bad = ~np.isfinite(w) | (w <= 0)
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(f"every omega must be a positive finite speed in rad/s; omega[{i}] = {w[i]!r} "
                         "(start a sweep just above zero, e.g. 1e-3)")
    return w


def warm_up() -> None:
    """Load the compiled kernels of the speed solver (banded HB, Hill cluster selection,
    Magnus monodromy and ladder, output extrema) by solving a one-coordinate model, so that
    worker processes forked afterwards start with them (the sweep engine's fork server)."""
    p = 8
    theta = 2 * np.pi * np.arange(p) / p
    model = OmegaSplitModel.from_samples(np.ones((p, 1, 1)), [np.full((p, 1, 1), 0.1)],
                                         [(1.0 + 0.2 * np.cos(theta))[:, None, None]], [np.cos(theta)[:, None]])
    with warnings.catch_warnings():  # only the kernels matter here: m = 2 truncates this model's exponents
        warnings.simplefilter("ignore", TruncationWarning)
        for method in ("dense", "magnus", "auto"):
            SpeedSolver(model, 2, stability=method).solve_many([0.7])
