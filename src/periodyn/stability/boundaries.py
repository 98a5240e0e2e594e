"""Stability boundaries along a speed range: where the largest real part of the
characteristic exponents crosses zero, refined by bisection, with the crossing type.

Types (Floquet multiplier leaving the unit circle, :mod:`periodyn.stability.crossings`):
"fold" (multiplier through +1; the paper's transcritical type, a resonance peak grows
unbounded), "period-doubling" (through -1, exponent i*omega/2), "neimark-sacker" (a complex pair).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.optimize import brentq

from ..errors import InputError
from ..system import RheoLinear
from .crossings import classify_crossing
from .floquet import FloquetExponents
from .methods import characteristic_exponents, check_method, stability_choice

__all__ = ["StabilityBoundary", "BoundaryCheck", "stability_boundaries", "crossing_type", "check_boundary"]


@dataclass(frozen=True)
class StabilityBoundary:
    """omega (rad/s) where max Re(lambda) = 0; kind: fold | period-doubling |
    neimark-sacker; becomes_stable: True if stable just above omega."""

    omega: float
    kind: str
    becomes_stable: bool


def crossing_type(exps: FloquetExponents, tol: float = 1e-3) -> str:
    """Type of the critical exponent (largest real part) from its multiplier's angle: a
    multiplier within tol pi of the real axis is real (:func:`periodyn.stability.crossings.classify_crossing`)."""
    mu = exps.multipliers[np.argmax(exps.exponents.real)]
    return classify_crossing(mu, tol=np.sin(tol * np.pi))


def stability_boundaries(system_at: Callable[[float], RheoLinear], omega: np.ndarray, harmonics: int,
                         stability: str = "auto", xtol: float = 1e-10, truncation: str = "refuse", *,
                         method: str | None = None) -> list[StabilityBoundary]:
    """Boundaries within a speed grid: each sign change of max Re(lambda) between grid
    neighbours is refined by Brent's method to ``xtol`` (relative to omega).

    system_at: omega -> RheoLinear (e.g. ``model.at``); omega: increasing grid, rad/s;
    stability: a stability method of :mod:`periodyn.stability.methods` (``method=``, its
    deprecated spelling, warns); truncation: "refuse" or "warn", for Hill results above the
    truncation tolerance (:func:`characteristic_exponents`).
    """
    if method is not None:
        stability = stability_choice(True if stability == "auto" else stability, method, "stability_boundaries")[1]
    method = check_method(stability)
    omega = np.asarray(omega, dtype=float)
    if omega.ndim != 1 or omega.size < 2 or np.any(np.diff(omega) <= 0):
        raise InputError("omega must be an increasing 1-D grid of at least two speeds (rad/s)")

    def max_real(w):
        return characteristic_exponents(system_at(w), harmonics, method, truncation=truncation).max_real

    values = np.array([max_real(w) for w in omega])
    out = []
    for i in np.nonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)[0]:
        w = brentq(max_real, omega[i], omega[i + 1], xtol=xtol * omega[i], rtol=4 * np.finfo(float).eps)
        side = omega[i] if values[i] > 0 else omega[i + 1]  # the unstable side names the type
        kind = crossing_type(characteristic_exponents(system_at(w + 0.5 * (side - w) * 1e-3), harmonics, method,
                                                      truncation=truncation))
        out.append(StabilityBoundary(float(w), kind, bool(values[i + 1] < 0)))
    return out


@dataclass(frozen=True)
class BoundaryCheck:
    """A boundary checked by the monodromy matrix of direct integration (DOP853) at
    omega (1 -+ step) just outside and inside the unstable side: max Re(lambda) (1/s)
    there, the crossing type the monodromy multipliers give inside, and whether both
    agree with the boundary (stable outside, unstable inside, same type)."""

    boundary: StabilityBoundary
    step: float
    max_real_outside: float
    max_real_inside: float
    kind_inside: str

    @property
    def agrees(self) -> bool:
        return self.max_real_outside < 0 < self.max_real_inside and self.kind_inside == self.boundary.kind


def check_boundary(system_at: Callable[[float], RheoLinear], boundary: StabilityBoundary,
                   step: float = 1e-3) -> BoundaryCheck:
    """Monodromy check of ``boundary`` at relative distance ``step`` on either side."""
    if not 0 < step < 0.5:
        raise InputError(f"step (relative distance from the boundary) must be in (0, 0.5), got {step!r}")
    inside = -step if boundary.becomes_stable else step
    out = characteristic_exponents(system_at(boundary.omega * (1 - inside)), 1, "monodromy")
    into = characteristic_exponents(system_at(boundary.omega * (1 + inside)), 1, "monodromy")
    return BoundaryCheck(boundary, step, float(out.max_real), float(into.max_real), crossing_type(into))
