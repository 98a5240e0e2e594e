"""Where stability is lost: the one classifier of how the critical Floquet multiplier
crosses the unit circle, used by stability boundaries over speed
(:mod:`periodyn.stability.boundaries`) and by the special points of continuation
(:mod:`periodyn.arclength.events`).

A multiplier mu counts as real when ``|Im mu| <= tol |mu|`` (|sin arg mu| <= tol). A loss
through +1 (real positive) is a "fold" (on a branch whose parameter keeps its direction a
"branch-point", which the continuation tells apart by dp/ds), through -1 (real negative) a
"period-doubling", and through a complex pair a "neimark-sacker".
"""

from __future__ import annotations

import numpy as np

__all__ = ["KINDS", "REAL_TOL", "is_real", "of_kind", "classify_crossing"]

#: loss type -> the kind of multiplier that crosses: "real > 0", "real < 0" or "complex"
KINDS = {"fold": "real > 0", "branch-point": "real > 0", "period-doubling": "real < 0", "neimark-sacker": "complex"}
REAL_TOL = 1e-6  # relative imaginary part below which a multiplier counts as real


def is_real(mu, tol: float = REAL_TOL) -> np.ndarray:
    """Whether each multiplier of mu (complex array) counts as real."""
    mu = np.asarray(mu, complex)
    return np.abs(mu.imag) <= tol * np.maximum(np.abs(mu), 1e-300)


def of_kind(mu, kind: str, tol: float = REAL_TOL) -> np.ndarray:
    """The multipliers of one kind of ``KINDS`` ("real > 0", "real < 0", "complex")."""
    mu = np.asarray(mu, complex)
    real = is_real(mu, tol)
    if kind == "complex":
        return mu[~real]
    return mu[real & ((mu.real > 0) if kind == "real > 0" else (mu.real < 0))]


def classify_crossing(mu: complex, continued: complex | None = None, tol: float = REAL_TOL) -> str:
    """Type of the stability loss of the critical multiplier mu: "neimark-sacker" when it
    (and ``continued``, the multiplier on the stable side that continues it, if given) is
    complex, else "period-doubling" when Re mu < 0, else "fold"."""
    crossing = [mu] if continued is None else [mu, continued]
    if not is_real(crossing, tol).any():
        return "neimark-sacker"
    return "period-doubling" if complex(mu).real < 0 else "fold"
