"""One speed, everything a sweep records: periodic solution, output harmonics and
amplitudes, and (optionally) the characteristic exponents.

:func:`solve_point` works on any :class:`RheoLinear`. :class:`SpeedSolver` serves a
constant-speed :class:`OmegaSplitModel`: the Hill/HB blocks are polynomials in omega
(``W = sum_p w^p W_p`` up to p = 4, ``V`` up to 2, ``Mh`` constant), so their terms, and
for small systems the real first-order Hill matrix terms, are built once per model and a
speed costs one polynomial evaluation, one sparse LU and one eigen-solve.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from .hb import (HillOperator, PeriodicSolution, _take, block_pattern, check_form, check_harmonics, check_sampling,
                 coefficient_band, hill_operator, output_spectrum, periodic_solution, solve_balance, system_spectra)
from .hill import _DENSE_MAX, FloquetExponents, check_method, first_order_matrix, operator_exponents, real_form
from .spectra import fourier_coefficients, synthesize
from .system import OmegaSplitModel, RheoLinear, Spectra
from .timedomain import exponents_from_monodromy, gauss_angles, magnus_steps, magnus_transition, monodromy_exponents

__all__ = ["PointResult", "solve_point", "SpeedSolver"]


@dataclass(frozen=True, eq=False)
class PointResult:
    """Results at one speed. omega rad/s; output_harmonics (2m+1, n_out) complex, l=-m..m;
    amplitude/mean (n_out,) half peak-to-peak and mean of the outputs; residual: relative
    HB residual; exponents/multipliers (2n,) complex (NaN without stability); max_real 1/s;
    stable (False also when stability was not computed)."""

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


def _point(sol: PeriodicSolution, stability: HillOperator | FloquetExponents | None, method: str,
           n: int) -> PointResult:
    """PointResult from a periodic solution and a Hill operator to solve (or exponents
    already found, or None without stability)."""
    if stability is not None:
        fl = stability if isinstance(stability, FloquetExponents) else operator_exponents(stability, method)
        exps, mults, max_real, stable = fl.exponents, fl.multipliers, fl.max_real, fl.stable
    else:
        exps = mults = np.full(2 * n, np.nan + 0j)
        max_real, stable = float("nan"), False
    return PointResult(sol.omega, sol.output_names, sol.output_harmonics, sol.output_amplitude(), sol.output_mean(),
                       sol.residual, exps, mults, max_real, stable)


def solve_point(system: RheoLinear, harmonics: int, stability: bool = True, method: str = "auto", *,
                form: str = "direct") -> PointResult:
    """Harmonic balance and, with ``stability``, Hill exponents (method as in
    :func:`periodyn.characteristic_exponents`) for one rheo-linear system."""
    m = check_harmonics(harmonics)
    method = check_method(method)
    op = hill_operator(system_spectra(system, m, form), system.omega, m)
    sol = periodic_solution(system, m, form=form, operator=op)
    if method in ("monodromy", "magnus") and stability:
        return _point(sol, monodromy_exponents(system, method), method, system.n)
    return _point(sol, op if stability else None, method, system.n)


class SpeedSolver:
    """Per-model precomputation for speed sweeps of an :class:`OmegaSplitModel`.

    ``solve(omega)`` gives the same :class:`PointResult` as
    ``solve_point(model.at(omega), harmonics, stability, method, form=form)``.
    """

    def __init__(self, model: OmegaSplitModel, harmonics: int, stability: bool = True, method: str = "auto",
                 form: str = "direct"):
        self.model = model
        self.m = m = check_harmonics(harmonics)
        self.stability = stability
        self.method = check_method(method)
        self.form = check_form(form)
        Ms, Cs, Ks, fs, Gs = model._power_spectra  # powers on the last axis
        if form == "inverse-mass":
            Minv = np.linalg.inv(model.mass)
            Cs = fourier_coefficients(np.einsum("pij,pjkq->pikq", Minv, np.moveaxis(model.damping, 0, -1)))
            Ks = fourier_coefficients(np.einsum("pij,pjkq->pikq", Minv, np.moveaxis(model.stiffness, 0, -1)))
            fs = fourier_coefficients(np.einsum("pij,pjq->piq", Minv, np.moveaxis(model.force, 0, -1)))
            Ms = np.zeros_like(Ms)
            Ms[(Ms.shape[0] - 1) // 2] = np.eye(model.n)
        self.output_spectra = Gs
        check_sampling(model.samples, m, Ms, Cs, Ks)
        band = max(coefficient_band(Spectra(Ms, Cs[..., j], Ks[..., i], None, None), m)
                   for j in range(Cs.shape[-1]) for i in range(Ks.shape[-1]))
        self.pattern = pat = block_pattern(m, model.n, band)
        d = pat.k_index - pat.l_index
        l = pat.l_index[:, None, None].astype(float)
        Md = _take(Ms, d)
        degree = max(Ks.shape[-1] - 1, Cs.shape[-1], 2)
        W = np.zeros((degree + 1,) + Md.shape, dtype=complex)
        V = np.zeros((max(Cs.shape[-1] - 1, 1) + 1,) + Md.shape, dtype=complex)
        for p in range(Ks.shape[-1]):
            W[p] += _take(Ks[..., p], d)
        for p in range(Cs.shape[-1]):
            Cd = _take(Cs[..., p], d)
            W[p + 1] += 1j * l * Cd
            V[p] += Cd
        W[2] -= l**2 * Md
        V[1] += 2j * l * Md
        self.W, self.V, self.Md = W, V, Md
        self.rhs = np.stack([_take(fs[..., p], np.arange(-m, m + 1)).reshape(-1) for p in range(fs.shape[-1])])
        K = (Ms.shape[0] - 1) // 2
        self.identity_mass = bool(np.array_equal(Ms[K], np.eye(model.n)) and not np.any(np.delete(Ms, K, axis=0)))
        self.real_terms = None
        if stability and self.method == "magnus":  # coefficients at the Gauss angles, per power of omega
            self.steps = magnus_steps(model.samples)
            theta = gauss_angles(self.steps)
            self.gauss = (synthesize(model._power_spectra[0], theta), synthesize(model._power_spectra[1], theta),
                          synthesize(model._power_spectra[2], theta))
        if stability and (self.method == "dense" or (self.method == "auto" and 2 * pat.size <= _DENSE_MAX)):
            # A(w) = sum_p w^p A_p with A_p = [[0, I if p = 0], [-Mh^-1 W_p, -Mh^-1 V_p]] (V_p = 0 past its degree)
            lu = None if self.identity_mass else sla.lu_factor(pat.dense(Md))
            V_padded = np.concatenate([V, np.zeros((len(W) - len(V),) + V.shape[1:], dtype=complex)])
            self.real_terms = np.stack([
                real_form(first_order_matrix(pat.dense(Wp), pat.dense(Vp), lu, identity=(p == 0)), m, model.n)
                for p, (Wp, Vp) in enumerate(zip(W, V_padded))])

    def operator(self, omega: float) -> HillOperator:
        """The Hill/HB operator at driving speed omega (rad/s)."""
        w = float(omega)
        if not np.isfinite(w) or w <= 0:
            from .errors import InputError

            raise InputError(f"omega must be a positive finite driving speed in rad/s, got {omega!r}")
        pw = w ** np.arange(len(self.W))
        real = None if self.real_terms is None else np.tensordot(pw, self.real_terms, 1)
        return HillOperator(w, self.pattern, (np.tensordot(pw, self.W, 1), np.tensordot(pw[: len(self.V)], self.V, 1),
                                              self.Md), pw[: len(self.rhs)] @ self.rhs, self.identity_mass, real)

    def solve(self, omega: float) -> PointResult:
        """Periodic solution and stability at one speed (rad/s)."""
        op = self.operator(omega)
        q, residual = solve_balance(op)
        model = self.model
        sol = PeriodicSolution(op.omega, q, output_spectrum(self.output_spectra, q), model.coordinate_names,
                               model.output_names, residual, self.form)
        if not self.stability:
            return _point(sol, None, self.method, model.n)
        if self.method == "monodromy":
            return _point(sol, monodromy_exponents(model.at(omega)), self.method, model.n)
        if self.method == "magnus":
            Mg, Cg, Kg = self.gauss
            Phi = magnus_transition(Mg, Cg @ op.omega ** np.arange(Cg.shape[-1]), Kg @ op.omega ** np.arange(Kg.shape[-1]),
                                    2 * np.pi / op.omega / self.steps)
            return _point(sol, exponents_from_monodromy(Phi, op.omega, "magnus"), self.method, model.n)
        return _point(sol, op, self.method, model.n)
