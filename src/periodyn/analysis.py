"""One speed, everything a sweep records: periodic solution, output harmonics and
amplitudes, and (optionally) the characteristic exponents."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .hb import check_harmonics, hill_operator, periodic_solution, system_spectra
from .hill import check_method, operator_exponents
from .system import RheoLinear

__all__ = ["PointResult", "solve_point"]


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


def solve_point(system: RheoLinear, harmonics: int, stability: bool = True, method: str = "auto", *,
                form: str = "direct") -> PointResult:
    """Harmonic balance and, with ``stability``, Hill exponents (method as in
    :func:`periodyn.characteristic_exponents`) for one rheo-linear system."""
    op = hill_operator(system_spectra(system, check_harmonics(harmonics), form), system.omega, harmonics)
    sol = periodic_solution(system, harmonics, form=form, operator=op)
    if stability:
        fl = operator_exponents(op, check_method(method))
        exps, mults, max_real, stable = fl.exponents, fl.multipliers, fl.max_real, fl.stable
    else:
        exps = mults = np.full(2 * system.n, np.nan + 0j)
        max_real, stable = float("nan"), False
    return PointResult(system.omega, system.output_names, sol.output_harmonics, sol.output_amplitude(),
                       sol.output_mean(), sol.residual, exps, mults, max_real, stable)
