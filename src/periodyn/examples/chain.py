"""Parametrically excited spring-mass chain: a scalable test and benchmark system.

n masses in a fixed-fixed chain; spring j has stiffness k (1 + eps cos(theta + phase_j))
and mass j carries a small rotating-unbalance-like mass modulation; stiffness-
proportional damping; forcing on the first mass. theta = omega t.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._arguments import require_physical
from ..system import OmegaSplitModel

__all__ = ["parametric_chain"]


def parametric_chain(n: int = 10, *, mass: float = 1.0, stiffness: float = 1.0e4, eps: float = 0.1,
                     mass_variation: float = 0.05, damping: float = 1e-4, samples: int = 64) -> OmegaSplitModel:
    """Chain of n masses (kg) and n+1 springs (N/m): first natural frequency about
    pi/(n+1) sqrt(k/m) ... highest about 2 sqrt(k/m) rad/s. Output: each mass displacement."""
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise InputError(f"chain needs n >= 1 masses, got {n!r}")
    require_physical("parametric_chain", {"mass": mass, "stiffness": stiffness}, {"damping": damping},
                     {"eps": eps, "mass_variation": mass_variation})
    if not abs(mass_variation) < 1:
        raise InputError(f"parametric_chain: mass_variation must be in (-1, 1) so every mass stays positive, got "
                         f"{mass_variation!r}")
    phases = 2 * np.pi * np.arange(n + 1) / (n + 1)

    def K(theta):
        k = stiffness * (1 + eps * np.cos(theta + phases))
        out = np.diag(k[:-1] + k[1:])
        out -= np.diag(k[1:-1], 1) + np.diag(k[1:-1], -1)
        return out

    K_mean = stiffness * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))

    def M(theta):
        return np.diag(mass * (1 + mass_variation * np.sin(theta + phases[:-1])))

    def f(theta):
        out = np.zeros(n)
        out[0] = np.cos(theta)
        return out

    return OmegaSplitModel.from_functions(M, [lambda th: damping * K_mean], [K], [f], samples,
                                          coordinate_names=tuple(f"x{j}" for j in range(n)),
                                          name=f"parametric_chain_{n}")
