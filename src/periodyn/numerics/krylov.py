"""GMRES with a right preconditioner, for linear solves with a factorization of a nearby matrix.

``gmres(matvec, b, precond, rtol=..., max_steps=...)`` minimizes the true residual
``|b - A x|`` (2-norm) over the Krylov space of ``A M^-1`` (no restarts: it is meant for
preconditioners that are exact factorizations of a matrix close to A, so that a few steps
suffice; when they do not, the caller refactorizes). Arnoldi with classical Gram-Schmidt
run twice (orthogonal to round-off); the small least-squares problem is solved at every
step for the residual estimate.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

__all__ = ["gmres"]


def gmres(matvec: Callable, b: np.ndarray, precond: Callable, *, rtol: float,
          max_steps: int) -> tuple[np.ndarray, float, int]:
    """x (n,) with ``|b - matvec(x)| <= rtol |b|`` if reached within max_steps Arnoldi steps.

    matvec(v) -> A v; precond(v) -> M^-1 v. Returns (x, relative residual |b - A x| / |b|
    of the returned x as the Arnoldi recurrence gives it, steps taken); x = 0 for b = 0.
    """
    n = len(b)
    beta = float(np.linalg.norm(b))
    if beta == 0.0:
        return np.zeros(n), 0.0, 0
    V = np.empty((max_steps + 1, n))
    Z = np.empty((max_steps, n))
    Hh = np.zeros((max_steps + 1, max_steps))
    V[0] = b / beta
    x, rel = np.zeros(n), 1.0
    for j in range(max_steps):
        Z[j] = precond(V[j])
        w = matvec(Z[j])
        h = V[:j + 1] @ w
        w = w - h @ V[:j + 1]
        h2 = V[:j + 1] @ w  # second pass: orthogonal to round-off
        w -= h2 @ V[:j + 1]
        Hh[:j + 1, j] = h + h2
        Hh[j + 1, j] = np.linalg.norm(w)
        e1 = np.zeros(j + 2)
        e1[0] = beta
        y = np.linalg.lstsq(Hh[:j + 2, :j + 1], e1, rcond=None)[0]
        rel = float(np.linalg.norm(e1 - Hh[:j + 2, :j + 1] @ y)) / beta
        x = y @ Z[:j + 1]
        if rel <= rtol or Hh[j + 1, j] <= 1e-300:
            return x, rel, j + 1
        V[j + 1] = w / Hh[j + 1, j]
    return x, rel, max_steps
