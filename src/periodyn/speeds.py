"""One speed, everything a sweep records: periodic solution, output harmonics and
amplitudes, and (optionally) the characteristic exponents.

:func:`solve_point` works on any :class:`RheoLinear`. :class:`SpeedSolver` serves a
constant-speed :class:`OmegaSplitModel`: the Hill/HB blocks are polynomials in omega
(``W = sum_p w^p W_p`` up to p = 4, ``V`` up to 2, ``Mh`` constant), so their terms are
built once per model, and a chunk of speeds costs polynomial evaluations, stacked LAPACK
solves and eigen-solves, and jitted kernels (:class:`SpeedBatch` holds the columns).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ConvergenceError, InputError
from .stability.floquet import is_stable
from .harmonic.operator import HarmonicOperator, HillOperator, check_harmonics
from .harmonic.batch_balance import DENSE_TERMS_BYTES, BalanceBatch
from .harmonic.balance import periodic_solution
from .stability.hill import (HILL_TIME_FACTOR, FloquetExponents, auto_exponents, check_method,
                   dense_exponents_batch, hill_costs_many, magnus_reason, operator_exponents)
from .kernels.solvers.floquet import magnus_monodromies
from .periodic import PeriodicSolution, half_range_and_mean, output_spectrum
from .numerics.spectra import StackedSpectra
from .system import OmegaSplitModel, RheoLinear
from .stability.magnus import (MagnusLadder, gauss_angles, half_period_signs, magnus_steps, magnus_terms,
                     monodromy_exponent_array)
from .stability.monodromy import monodromy_exponents

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


def _point(sol: PeriodicSolution, stability: HillOperator | FloquetExponents | None, method: str,
           n: int) -> PointResult:
    """PointResult from a periodic solution and a Hill operator to solve (or exponents
    already found, or None without stability)."""
    if stability is not None:
        fl = stability if isinstance(stability, FloquetExponents) else operator_exponents(stability, method)
        exps, mults, max_real, stable = fl.exponents, fl.multipliers, fl.max_real, fl.stable
        used, reason = fl.method, fl.reason
    else:
        exps = mults = np.full(2 * n, np.nan + 0j)
        max_real, stable, used, reason = float("nan"), False, "", ""
    return PointResult(sol.omega, sol.output_names, sol.output_harmonics, sol.output_amplitude(), sol.output_mean(),
                       sol.residual, exps, mults, max_real, stable, used, reason)


def solve_point(system: RheoLinear, harmonics: int, stability: bool = True, method: str = "auto", *,
                form: str = "direct") -> PointResult:
    """Harmonic balance and, with ``stability``, Hill exponents (method as in
    :func:`periodyn.characteristic_exponents`) for one rheo-linear system."""
    m = check_harmonics(harmonics)
    method = check_method(method)
    op = HarmonicOperator.for_system(system, m, form).at(system.omega)
    sol = periodic_solution(system, m, form=form, operator=op)
    if method in ("monodromy", "magnus") and stability:
        return _point(sol, monodromy_exponents(system, method), method, system.n)
    if method == "auto" and stability:
        return _point(sol, auto_exponents(system, op), method, system.n)
    return _point(sol, op if stability else None, method, system.n)


@dataclass(frozen=True, eq=False)
class SpeedBatch:
    """Results at S speeds, columnar (the fields of :class:`PointResult` with a leading
    speed axis). message: (S,) str, empty where the point was solved, else why it failed
    (its stability entries are then NaN and ``stable`` False); method: (S,) str, the
    stability method used at each speed ("" without stability)."""

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
                                                             dtype=str))

    def point(self, i: int) -> PointResult:
        """The PointResult of speed i."""
        return PointResult(float(self.omega[i]), self.output_names, self.output_harmonics[i], self.amplitude[i],
                           self.mean[i], float(self.residual[i]), self.exponents[i], self.multipliers[i],
                           float(self.max_real[i]), bool(self.stable[i]), str(self.method[i]))


_BATCH_ELEMENTS = 4_000_000  # matrix entries per stacked LAPACK call (memory of a speed chunk)
_EXP_MAX = np.log(np.finfo(float).max)  # largest Re(lambda) T whose multiplier exp(lambda T) is finite
# speed_costs (load balance of sweeps): HB multiply-adds per second and set-up per speed
# (Cardan shaft 0.1 ms, slider-crank 0.05 ms per speed measured on one core), and the
# Magnus climb over its first comparison (Cardan shaft: 6.6-10.7x measured over 0-1 omega_b)
_HB_RATE, _HB_SETUP = 1e10, 5e-6
_CLIMB_FACTOR = 8.0
_MONODROMY_SECONDS = 1e-3  # DOP853 over one period at the sweep's highest speed (steps grow with the period)


class SpeedSolver:
    """Per-model precomputation for speed sweeps of an :class:`OmegaSplitModel`.

    The Hill/HB blocks are polynomials in omega; their terms, and where they pay off the
    terms of the real HB matrix, of the real first-order Hill matrix (dense Hill) or of
    the Magnus system matrix at the Gauss angles, are built once. ``solve_many(omegas)``
    then treats a chunk of speeds with stacked LAPACK calls and jitted kernels; the
    large-system paths (banded/sparse HB, ARPACK Hill, DOP853 monodromy) go speed by speed.
    ``solve(omega)`` gives the same :class:`PointResult` as
    ``solve_point(model.at(omega), harmonics, stability, method, form=form)``.
    """

    def __init__(self, model: OmegaSplitModel, harmonics: int, stability: bool = True, method: str = "auto",
                 form: str = "direct"):
        self.model = model
        self.m = check_harmonics(harmonics)
        self.stability = stability
        self.method = check_method(method)
        self.form = form
        self.harmonic = op = HarmonicOperator.for_model(model, self.m, form)
        self.output_spectra = model._power_spectra[4]
        self.pattern = op.pattern
        # HB per chunk of speeds: jitted banded LU for narrow small bands; stacked real dense
        # LAPACK (in half-period symmetry classes) for small systems whose band is wide;
        # otherwise speed by speed
        self.balance = BalanceBatch(op, half_period_signs(*model._power_spectra[:3]))
        self.storage, self.batch_balance = self.balance.storage, self.balance.kind
        self.magnus = None
        if stability and self.method == "magnus":
            theta = gauss_angles(magnus_steps(model.samples))
            self.magnus = magnus_terms(*StackedSpectra(*model._power_spectra[:3]).at(theta))[0]
        # stacked dense Hill evaluates the precomputed real first-order Hill terms
        # (PW, 2N, 2N) while they fit in DENSE_TERMS_BYTES; a larger model builds its dense
        # Hill matrix speed by speed (the terms of the 32-element slider-crank at m = 32: 2.8 GB)
        self.dense_hill = (stability and self.method in ("dense", "auto")
                           and 8.0 * len(op.W) * (2 * self.pattern.size) ** 2 <= DENSE_TERMS_BYTES)
        self.ladder = MagnusLadder(*model._power_spectra[:3]) if stability and self.method == "auto" else None

    def operator(self, omega: float) -> HillOperator:
        """The Hill/HB operator at driving speed omega (rad/s)."""
        return self.harmonic.at(check_speeds(omega)[0], real_first_order=self.method == "dense" and self.dense_hill)

    def hill_methods(self, omegas) -> list[tuple[str, str, float]]:
        """Hill method at each speed (rad/s), why, and its estimated seconds: "auto"
        chooses per speed by estimated cost (:func:`periodyn.stability.hill.choose_method`), as the
        per-speed path does."""
        w = check_speeds(omegas)
        if self.method != "auto":
            return [(self.method, "requested", np.inf)] * w.size
        return [(m, r, c) for m, c, r in hill_costs_many(self.harmonic, w)]

    def stability_methods(self, omegas) -> list[tuple[str, str]]:
        """Stability method at each speed (rad/s) and why (for "auto": Magnus where its
        error estimate certifies the verdict within Hill's estimated cost, else Hill)."""
        w = check_speeds(omegas)
        if self.method != "auto":
            return [(self.method, "requested")] * w.size
        return [(m, r) for m, r in zip(*self._auto(w)[1:])]

    def _auto(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Magnus exponents (S, 2n) where accepted, method names (S,) and reasons (S,)."""
        hill = self.hill_methods(w)
        seconds = np.array([c for _, _, c in hill])
        est = self.ladder.solve(w, seconds * HILL_TIME_FACTOR)
        first = est.first_cost
        methods = np.array(["magnus" if ok else h for ok, (h, _, _) in zip(est.accepted, hill)], dtype=object)
        reasons = np.array([magnus_reason(est, i, hill[i][0], seconds[i], first[i]) for i in range(w.size)],
                           dtype=object)
        return est.exponents, methods, reasons

    def speed_costs(self, omegas) -> np.ndarray:
        """Estimated seconds (S,) of each speed (rad/s), for sharing a sweep's work out
        evenly and judging whether worker processes pay (a rough estimate: measured chunk
        times were 0.8-2.9x it on the Cardan shaft). The harmonic balance costs the same
        at every speed (its LU: the cheaper of N^3/3 dense and 2 N u^2 banded multiply-adds, at
        _HB_RATE, plus a set-up); "auto" adds its Magnus climb (_CLIMB_FACTOR times the
        ladder's estimate of the first comparison, which grows as the speed falls: the
        steps must resolve the stiffest mode over a longer period), at most what the
        budget rule lets it spend before Hill takes over; "monodromy" adds its integration
        over one period (nominally _MONODROMY_SECONDS at the highest speed, in proportion
        to the period); the other methods cost the same at every speed."""
        w = check_speeds(omegas)
        pat = self.pattern
        hb = _HB_SETUP + min(pat.size**3 / 3.0, 2.0 * pat.size * pat.half_bandwidth**2) / _HB_RATE
        if not self.stability or self.method not in ("auto", "monodromy"):
            return np.full(w.size, hb)
        if self.method == "monodromy":
            return hb + _MONODROMY_SECONDS * w.max() / w
        hill = np.array([c for _, _, c in self.hill_methods(w)])
        climb = np.minimum(_CLIMB_FACTOR * self.ladder.first_cost(w), HILL_TIME_FACTOR * hill)
        return hb + climb + np.where(climb >= HILL_TIME_FACTOR * hill, hill, 0.0)

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
        chunk = int(np.clip(_BATCH_ELEMENTS // per_speed, 1, 256))
        parts = [self._solve_chunk(w[i: i + chunk]) for i in range(0, w.size, chunk)]
        if len(parts) == 1:
            return parts[0]
        return SpeedBatch(w, self.model.output_names,
                          *(np.concatenate([getattr(b, f) for b in parts]) for f in SpeedBatch.__dataclass_fields__
                            if f not in ("omega", "output_names")))

    def _balance(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Harmonics (S, 2m+1, n), relative HB residuals (S,) and failure messages (S,)
        at speeds w (S,) by the path ``batch_balance`` (:mod:`periodyn.harmonic.batch_balance`)."""
        return self.balance.solve_many(w, self.batch_balance)

    def _stability(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Exponents (S, 2n) (NaN where failed), failure messages (S,) and the method used
        (S,) at speeds w."""
        n, m = self.model.n, self.m
        exps = np.full((w.size, 2 * n), np.nan + 0j)
        message = np.full(w.size, "", dtype=object)
        if self.magnus is not None:
            Phi = np.empty((w.size, 2 * n, 2 * n))
            magnus_monodromies(self.magnus, w, Phi)
            finite = np.isfinite(Phi).all(axis=(1, 2))
            exps[finite] = monodromy_exponent_array(Phi[finite], w[finite])
            for i in np.nonzero(~finite)[0]:
                message[i] = (f"the Magnus monodromy matrix at omega = {w[i]:.6g} rad/s is not finite; use "
                              "method='monodromy' (adaptive steps) or check the model's coefficients")
            for i in np.nonzero(finite & np.isnan(exps).any(axis=1))[0]:
                message[i] = (f"the Magnus monodromy matrix at omega = {w[i]:.6g} rad/s is singular: a mode decays "
                              "by more than 1e-308 in one period, so its exponent is not determined; use Hill's "
                              "method (method='dense' or 'sparse') or check the model's damping")
            return exps, message, np.full(w.size, "magnus", dtype=object)
        if self.ladder is not None:
            magnus, methods, _ = self._auto(w)
            accepted = methods == "magnus"
            exps[accepted] = magnus[accepted]
        else:
            methods = np.array([name for name, _, _ in self.hill_methods(w)], dtype=object)
        stacked = (methods == "dense") & self.dense_hill
        dense = np.nonzero(stacked)[0]
        if dense.size:
            exps[dense], _, found = dense_exponents_batch(self.harmonic.real_first_order_many(w[dense]), w[dense], m, n)
            for i in dense[found < 2 * n]:
                exps[i] = np.nan
                message[i] = (f"Hill's method with m = {m} resolved {found[dense == i][0]} of {2 * n} exponent "
                              f"clusters at omega = {w[i]:.6g} rad/s; increase harmonics")
        for i in np.nonzero(~stacked & (methods != "magnus"))[0]:
            try:
                if methods[i] == "monodromy":
                    exps[i] = monodromy_exponents(self.model.at(w[i])).exponents
                else:
                    exps[i] = operator_exponents(self.harmonic.at(w[i]), methods[i]).exponents
            except ConvergenceError as exc:
                message[i] = str(exc) or type(exc).__name__
        # the multiplier exp(lambda T) must be a number: Re(lambda) T above the double range is no exponent
        growth = exps.real.max(axis=1) * (2 * np.pi / w)
        for i in np.nonzero((message == "") & (growth > _EXP_MAX))[0]:
            exps[i] = np.nan
            message[i] = (f"an exponent at omega = {w[i]:.6g} rad/s has Re(lambda) T = {growth[i]:.3g}, beyond the "
                          "range of the multiplier exp(lambda T): the model's coefficients are out of the range the "
                          "solver resolves (rescale it or add harmonics)")
        return exps, message, methods

    def _solve_chunk(self, w: np.ndarray) -> SpeedBatch:
        q, residual, balance_message = self._balance(w)
        spectrum = output_spectrum(self.output_spectra, q)  # (S, 2M+1, n_out)
        S, H, n_out = spectrum.shape
        half, mean = half_range_and_mean(np.moveaxis(spectrum, 0, 1).reshape(H, S * n_out))
        M = (H - 1) // 2
        harmonics = spectrum[:, M - self.m: M + self.m + 1]
        if self.stability:
            exps, message, methods = self._stability(w)
            multipliers = np.exp(exps * (2 * np.pi / w)[:, None])
            max_real = exps.real.max(axis=1)
            stable = is_stable(max_real, 2 * np.pi / w)  # False where NaN (failed)
        else:
            exps = multipliers = np.full((S, 2 * self.model.n), np.nan + 0j)
            max_real, stable, message = np.full(S, np.nan), np.zeros(S, dtype=bool), np.full(S, "", dtype=object)
            methods = message
        failed = balance_message != ""  # no periodic solution: the point fails with the HB's reason
        message = np.where(failed, balance_message, message)
        columns = (np.where(failed.reshape((S,) + (1,) * (a.ndim - 1)), np.nan, a)
                   for a in (harmonics, half.reshape(S, n_out), mean.reshape(S, n_out), residual, exps, multipliers,
                             max_real))
        return SpeedBatch(w, self.model.output_names, *columns, stable & ~failed, message.astype(str),
                          methods.astype(str))


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
    for method in ("dense", "magnus", "auto"):
        SpeedSolver(model, 2, method=method).solve_many([0.7])
