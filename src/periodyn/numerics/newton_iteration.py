"""The one Newton iteration of periodyn's non-linear solvers (IHB, shooting, consistent
initial states, the continuation corrector).

``newton(system_of_equations, x0, ...)`` with ``system_of_equations(x) -> (R, J)``; the
linear solves go through a factory ``factor(J) -> solve(b)`` (default: SuperLU for sparse
J, LAPACK LU for dense square J; least squares gives Gauss-Newton for non-square J).
Convergence is measured in the max-norm of R. A failure raises ConvergenceError naming the
residual, the iteration count and what to try; it is never returned.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import ConvergenceError

__all__ = ["NewtonResult", "newton", "lu_factor", "least_squares_factor"]


@dataclass(frozen=True, eq=False)
class NewtonResult:
    """Converged point x (N,); residual: max|R(x)|; iterations: Newton updates done;
    jacobian: J at x; solve: factorization of the last J used for an update (None when
    x0 already converged), reusable for a nearby linear solve (continuation tangent)."""

    x: np.ndarray
    residual: float
    iterations: int
    jacobian: object
    solve: Callable | None


def lu_factor(J) -> Callable:
    """solve(b) for a square J: SuperLU when sparse (through ``J.fill_ordering.factor`` when
    the matrix carries an ordering kept for its pattern), LAPACK LU when dense."""
    ordering = getattr(J, "fill_ordering", None)
    if ordering is not None:
        return ordering.factor(J)
    if sp.issparse(J):
        return spla.splu(sp.csc_matrix(J)).solve
    # LAPACK getrf/getrs directly (scipy's checking wrappers cost more than a small orbit's solve)
    J = np.asarray(J)
    getrf, getrs = _LAPACK_LU if J.dtype == np.float64 else sla.get_lapack_funcs(("getrf", "getrs"), (J,))
    lu, piv, info = getrf(J)
    if info > 0:  # an exactly zero pivot is an error here, not a warning
        raise sla.LinAlgWarning(f"Diagonal number {info} is exactly zero. Singular matrix.")

    def solve(b):
        x, err = getrs(lu, piv, b)
        if err:
            raise ValueError(f"LAPACK getrs: illegal argument {-err}")
        return x
    return solve


_LAPACK_LU = sla.get_lapack_funcs(("getrf", "getrs"), (np.empty((1, 1)),))


def least_squares_factor(J) -> Callable:
    """solve(b): minimum-norm least-squares solution (Gauss-Newton for m x n J)."""
    return lambda b: np.linalg.lstsq(J, b, rcond=None)[0]


def newton(equations: Callable, x0, *, tol: float, max_iter: int, factor: Callable = lu_factor,
           residual: Callable | None = None, backtrack: int = 0, accept: float = 1.0,
           label: str = "Newton", hint: str = "start closer to the solution") -> NewtonResult:
    """Solve R(x) = 0 from x0.

    equations(x) -> (R (N,), J); factor(J) -> solve(b); tol: max|R| to reach; max_iter:
    updates allowed. Backtracking (``backtrack`` > 0 trial steps): a step is halved while
    ``max|residual(x + s dx)| >= accept * max|R(x)|`` (``residual`` defaults to the first
    output of ``equations``; a ConvergenceError of a trial counts as a rejection).
    label/hint: what is being solved and what to try, for the error message.
    """
    resid = residual or (lambda x: equations(x)[0])
    x = np.array(x0, dtype=float)
    solve, rn = None, np.inf
    for it in range(max_iter + 1):
        R, J = equations(x)
        rn = float(np.abs(R).max(initial=0.0))
        if not np.isfinite(rn):
            break
        if rn <= tol:
            return NewtonResult(x, rn, it, J, solve)
        if it == max_iter:
            break
        try:
            solve = factor(J)
            dx = -solve(R)
        except (RuntimeError, np.linalg.LinAlgError, ValueError, sla.LinAlgWarning) as exc:
            raise ConvergenceError(f"{label}: singular Jacobian at iteration {it} (residual {rn:.3g}, {exc}); {hint}",
                                   rn, it) from None
        if not np.all(np.isfinite(dx)):
            break
        step = 1.0  # trial steps 1, 1/2, ..., 2^(1-backtrack); the last is taken when none is accepted
        for k in range(backtrack):
            try:
                if float(np.max(np.abs(resid(x + step * dx)))) < accept * rn:
                    break
            except ConvergenceError:
                pass
            if k < backtrack - 1:
                step *= 0.5
        x = x + step * dx
    raise ConvergenceError(f"{label} did not converge: residual {rn:.3g} > tol {tol:.1g} after {it} iterations; {hint}",
                           rn, it)
