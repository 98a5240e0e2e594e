"""Independent oracles for benchmarks/property_run.py: the physics a result must obey,
computed without periodyn's solvers (SciPy's DOP853 on equations written out here).

- ``mathieu_reference``: the linearized elliptic pendulum, eq. (29) of Schwab & Meijaard,
  a forced damped Mathieu equation, integrated with its variational equations over one
  period: the monodromy matrix (multipliers, verdict) and the periodic orbit
  x0 = (I - Phi)^-1 x_p(T) (amplitude, half peak-to-peak).
- ``linear_reference``: the same for M q'' + C(t) q' + K(t) q = f(t) with constant M and
  coefficients given as functions of the angle theta = omega t.
- Liouville: the multipliers' product is exp(integral of tr A over a period).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

G = 9.81


class Wrong(Exception):
    """A result that disagrees with its oracle (or a broken input that was accepted)."""


@dataclass(frozen=True)
class Reference:
    """Monodromy multipliers (2n,), the periodic orbit's amplitude per coordinate (n,)
    and the smallest |1 - mu| (how well the periodic orbit is determined)."""

    multipliers: np.ndarray
    amplitude: np.ndarray
    period: float

    @property
    def log_growth(self) -> float:
        """log max|mu| per period (> 0: unstable)."""
        return float(np.log(np.abs(self.multipliers).max()))

    @property
    def conditioning(self) -> float:
        return float(np.abs(1.0 - self.multipliers).min())


def linear_reference(M: np.ndarray, C, K, f, omega: float, samples: int = 256) -> Reference:
    """Reference for M q'' + C(th) q' + K(th) q = f(th), th = omega t; C, K: th -> (n,n),
    f: th -> (n,)."""
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    T = 2 * np.pi / omega

    def A(t):
        th = omega * t
        return np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K(th), -Minv @ C(th)]])

    def b(t):
        return np.r_[np.zeros(n), Minv @ f(omega * t)]

    def rhs(t, y):
        X = y[2 * n:].reshape(2 * n, 2 * n)
        return np.r_[A(t) @ y[:2 * n] + b(t), (A(t) @ X).ravel()]

    y0 = np.r_[np.zeros(2 * n), np.eye(2 * n).ravel()]
    sol = solve_ivp(rhs, (0.0, T), y0, method="DOP853", rtol=1e-11, atol=1e-13)
    Phi = sol.y[2 * n:, -1].reshape(2 * n, 2 * n)
    x0 = np.linalg.solve(np.eye(2 * n) - Phi, sol.y[:2 * n, -1])
    t = np.linspace(0.0, T, samples, endpoint=False)
    orbit = solve_ivp(lambda t, x: A(t) @ x + b(t), (0.0, T), x0, method="DOP853", rtol=1e-11, atol=1e-13,
                      t_eval=t).y[:n]
    return Reference(np.linalg.eigvals(Phi), 0.5 * np.ptp(orbit, axis=1), T)


def mathieu_reference(omega: float, length: float, radius: float, eccentricity: float, zeta: float,
                      g: float = G) -> Reference:
    """Eq. (29): phi'' + 2 zeta w0 phi' + [w0^2 + (1+e) rho w^2 cos th] phi
    = -2 zeta w0 w + (1-e) rho w^2 sin th, w0 = sqrt(g/l), rho = r/l."""
    w0, rho, e = np.sqrt(g / length), radius / length, eccentricity
    return linear_reference(np.eye(1), lambda th: np.array([[2 * zeta * w0]]),
                            lambda th: np.array([[w0 ** 2 + (1 + e) * rho * omega ** 2 * np.cos(th)]]),
                            lambda th: np.array([-2 * zeta * w0 * omega + (1 - e) * rho * omega ** 2 * np.sin(th)]),
                            omega)


def liouville_product(trace: float, period: float) -> float:
    """Product of the multipliers of a flow whose Jacobian has constant trace ``trace``."""
    return float(np.exp(trace * period))
