"""Time-domain reference solutions of rheo-linear systems: the monodromy matrix and the
direct integration of ``M(t) q'' + C(t) q' + K(t) q = f(t)``.

The coefficients are evaluated from the exact callables when the system was built with
``RheoLinear.from_functions``, otherwise by trigonometric interpolation of the samples
(their Fourier series). Integration: scipy DOP853 at rtol 1e-11.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from .errors import ConvergenceError
from .system import RheoLinear

__all__ = ["first_order_matrix", "monodromy_matrix", "monodromy_exponents", "integrate"]

RTOL, ATOL = 1e-11, 1e-13


def _coefficients(system: RheoLinear):
    """Callable t -> (M, C, K, f) at time t (s)."""
    if system.functions is not None:
        Mf, Cf, Kf, ff = system.functions
        n = system.n

        def at(t):
            return (np.asarray(Mf(t), float).reshape(n, n), np.asarray(Cf(t), float).reshape(n, n),
                    np.asarray(Kf(t), float).reshape(n, n), np.asarray(ff(t), float).reshape(n))

        return at
    S = system.spectra
    K = (S.mass.shape[0] - 1) // 2
    k = np.arange(-K, K + 1)

    def at(t):
        e = np.exp(1j * k * system.omega * t)
        return tuple(np.tensordot(e, X, 1).real for X in (S.mass, S.damping, S.stiffness, S.force))

    return at


def first_order_matrix(system: RheoLinear):
    """Callables t -> A(t) (2n, 2n) and t -> b(t) (2n,) of y' = A y + b, y = [q, q']."""
    coeff = _coefficients(system)
    n = system.n

    def A_b(t):
        M, C, K, f = coeff(t)
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        A[n:, :n] = -np.linalg.solve(M, K)
        A[n:, n:] = -np.linalg.solve(M, C)
        b = np.concatenate([np.zeros(n), np.linalg.solve(M, f)])
        return A, b

    return A_b


def monodromy_matrix(system: RheoLinear) -> np.ndarray:
    """Fundamental matrix after one period, Phi(T) with Phi(0) = I, (2n, 2n)."""
    A_b = first_order_matrix(system)
    m2 = 2 * system.n

    def rhs(t, y):
        return (A_b(t)[0] @ y.reshape(m2, m2)).reshape(-1)

    sol = solve_ivp(rhs, (0.0, system.period), np.eye(m2).reshape(-1), method="DOP853", rtol=RTOL, atol=ATOL)
    if not sol.success:
        raise ConvergenceError(f"monodromy integration failed at omega = {system.omega:.6g} rad/s: {sol.message}")
    return sol.y[:, -1].reshape(m2, m2)


def monodromy_exponents(system: RheoLinear):
    """Characteristic exponents from the eigenvalues of the monodromy matrix (principal
    logarithm, |Im| <= omega/2)."""
    from .hill import FloquetExponents

    mu = np.linalg.eigvals(monodromy_matrix(system))
    lam = np.log(mu.astype(complex)) / system.period
    order = np.lexsort((lam.imag, lam.real))
    nan = np.full(lam.size, np.nan)
    return FloquetExponents(system.omega, lam[order], nan, nan, "monodromy")


def integrate(system: RheoLinear, y0, t) -> np.ndarray:
    """Direct solution y = [q, q'] of the forced linear equations from y(0) = y0 (2n,) at
    times t (s, increasing from 0) -> (len(t), 2n)."""
    A_b = first_order_matrix(system)
    t = np.asarray(t, dtype=float)

    def rhs(tt, y):
        A, b = A_b(tt)
        return A @ y + b

    sol = solve_ivp(rhs, (0.0, float(t[-1])), np.asarray(y0, dtype=float), method="DOP853", t_eval=t,
                    rtol=RTOL, atol=ATOL)
    if not sol.success:
        raise ConvergenceError(f"time integration failed: {sol.message}")
    return sol.y.T
