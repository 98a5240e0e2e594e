"""Newton steps of the shooting corrector that reuse the latest Jacobian.

A shooting Jacobian costs a variational integration (the trajectory with 2r more columns
and the parameter sensitivity), a residual only a plain one, several times cheaper. Along
a continuation the Jacobian at the previous point is close to the one at the next, so
:class:`ChordEquations` answers ``equations(X, omega, P)`` with the plain residual and the
latest Jacobian updated by Broyden's rank-one secant formula (using dR/dp for the
parameter change), and integrates the variational equations only

* where no Jacobian is at hand yet,
* once the residual is within the tolerance (the converged point then carries its exact
  Jacobian: tangent, fold test and multipliers use it, never an updated one),
* when a reused-Jacobian step did not halve the residual (convergence check).
"""

from __future__ import annotations

import numpy as np

__all__ = ["ChordEquations"]

_LOOSE = 1e-8  # integration tolerance of the Jacobian at a predictor


class ChordEquations:
    """``equations(X, omega, P) -> (R, J)`` and ``parameter_derivative`` for a Newton
    corrector on ``problem`` (a ShootingProblem) with residual tolerance ``tol``."""

    def __init__(self, problem, tol: float):
        self.problem, self.tol = problem, float(tol)
        self._state = None  # (X, p, R, J, dR/dp, reused steps since the last exact Jacobian)
        self.exact = self.reused = 0  # counts, for the record
        self._next_exact = False

    def _p(self, omega, P):
        name = self.problem.parameter
        return float(omega if name is None else P[name])

    def _rtol(self, rn):
        """Integration tolerance for a chord step from a residual of rn: its error stays a
        ten-thousandth of the residual still to remove (inexact Newton), never below the problem's."""
        return float(np.clip(1e-4 * rn, self.problem.rtol, _LOOSE))

    def _exact(self, X, omega, P, converged=False):
        """R, J and dR/dp; at a (nearly) converged point at the problem's tolerance with the
        orbit samples, at a predictor at a loose tolerance (J serves the chord steps only)."""
        R, J, Rp, _ = self.problem.evaluate(X, omega, P, sensitivity=True, samples=converged,
                                            rtol=None if converged or self._state is None else _LOOSE)
        self._state = (X.copy(), self._p(omega, P), R, J.copy(), Rp, 0)
        self._next_exact = False
        self.exact += 1
        return R, J

    def equations(self, X, omega, P):
        X = np.asarray(X, float)
        st = self._state
        if st is None or float(np.max(np.abs(st[2]))) <= self.tol:  # a new corrector: exact J at the predictor
            return self._exact(X, omega, P)
        if self._next_exact:  # the reused-Jacobian rate predicts convergence here
            return self._exact(X, omega, P, converged=True)
        X0, p0, R0, J, Rp, steps = st
        r0 = float(np.max(np.abs(R0)))
        R = self.problem.residual(X, omega, P, rtol=self._rtol(r0))
        rn = float(np.max(np.abs(R)))
        if rn <= self.tol:
            return self._exact(X, omega, P, converged=True)
        if (steps and rn > 0.5 * r0) or not np.isfinite(rn):
            return self._exact(X, omega, P)
        dX, dp = X - X0, self._p(omega, P) - p0
        nx = float(dX @ dX)
        if nx > 0:
            J = J + np.outer(R - R0 - J @ dX - Rp * dp, dX) / nx
        self._state = (X.copy(), self._p(omega, P), R, J, Rp, steps + 1)
        self._next_exact = rn * rn / r0 <= self.tol
        self.reused += 1
        return R, J

    def parameter_derivative(self, X, omega, P) -> np.ndarray:
        """dR/dp of the latest exact evaluation (used only in the bordering rows)."""
        if self._state is None:
            return self.problem.parameter_derivative(X, omega, P)
        return self._state[4]
