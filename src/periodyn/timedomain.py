"""Time-domain solutions of rheo-linear systems: the monodromy matrix and the direct
integration of ``M(t) q'' + C(t) q' + K(t) q = f(t)``.

Two monodromy integrators:
* the reference, DOP853 through the one integrator wrapper (``periodyn.nonlinear.integrate.solve``)
  at rtol 1e-11 on the exact callables (systems built with
  ``RheoLinear.from_functions``) or on the Fourier series of the samples;
* ``magnus``: the fixed-step 4th-order Magnus integrator with two Gauss points per step,
  ``Phi <- exp(h/2 (A1 + A2) + sqrt(3)/12 h^2 [A2, A1]) Phi``, which treats stiff, heavily
  damped element modes exactly in the frozen part and costs one batch of small matrix
  exponentials per speed (used by fast stability sweeps and the DAE stability analysis).
"""

from __future__ import annotations

import numpy as np

from .errors import ConvergenceError
from .floquet import FloquetExponents
from .kernels.floquet import magnus_product
from .nonlinear.integrate import solve
from .spectra import synthesize
from .system import RheoLinear

__all__ = ["first_order_matrix", "monodromy_matrix", "monodromy_exponents", "integrate", "gauss_angles",
           "magnus_terms", "magnus_transition", "magnus_steps", "monodromy_exponent_array"]

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

    return solve(rhs, (0.0, system.period), np.eye(m2).reshape(-1), rtol=RTOL, atol=ATOL).y[:, -1].reshape(m2, m2)


def magnus_steps(samples: int) -> int:
    """Default Magnus steps per period for coefficients sampled p times: max(128, 2p)."""
    return max(128, 2 * samples)


def gauss_angles(steps: int, start: float = 0.0, stop: float = 2 * np.pi) -> np.ndarray:
    """Angles of the two Gauss points of each of ``steps`` equal steps, (2 steps,), rad."""
    g = np.sqrt(3) / 6
    frac = (np.arange(steps)[:, None] + np.array([0.5 - g, 0.5 + g])[None, :]).ravel() / steps
    return start + (stop - start) * frac


def magnus_terms(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray) -> tuple[np.ndarray, float]:
    """Terms of the balanced first-order system matrix for the Magnus kernels.

    mass (g, n, n), damping (g, n, n, Pc), stiffness (g, n, n, Pk) at g points, the last
    axis holding the coefficients of powers of omega. Returns terms (max(Pc, Pk), g, 2n, 2n)
    with ``A = sum_p omega^p terms[p]`` the matrix of y' = A y for y = (a q, q'), and the
    balancing scale a = sqrt(max ||M^-1 K_0||_inf) (1/s), which brings the stiff blocks to
    the same size (a similarity: the transition matrix of (q, q') is D^-1 Phi D,
    D = diag(a I, I), with the same eigenvalues)."""
    g, n = mass.shape[:2]
    Pc, Pk = damping.shape[-1], stiffness.shape[-1]
    MinvC = np.linalg.solve(mass, damping.reshape(g, n, n * Pc)).reshape(g, n, n, Pc)
    MinvK = np.linalg.solve(mass, stiffness.reshape(g, n, n * Pk)).reshape(g, n, n, Pk)
    top = float(np.abs(MinvK[..., 0]).sum(axis=2).max()) if g else 0.0
    a = np.sqrt(top) if top > 0 else 1.0
    terms = np.zeros((max(Pc, Pk), g, 2 * n, 2 * n))
    terms[0, :, :n, n:] = a * np.eye(n)
    terms[:Pk, :, n:, :n] = -np.moveaxis(MinvK, -1, 0) / a
    terms[:Pc, :, n:, n:] = -np.moveaxis(MinvC, -1, 0)
    return terms, a


def magnus_transition(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, h: float) -> np.ndarray:
    """Transition matrix (2n, 2n) of y' = A(t) y, y = (q, q'), over equal steps h (s).

    mass/damping/stiffness: (2 steps, n, n) at the two Gauss points of each step (see
    :func:`gauss_angles`); the jitted 4th-order Magnus kernel on the balanced system."""
    n = mass.shape[1]
    terms, a = magnus_terms(mass, damping[..., None], stiffness[..., None])
    phi = np.empty((2 * n, 2 * n))
    magnus_product(terms[0], float(h), phi)
    phi[:n, n:] /= a  # undo the balancing: Phi = D^-1 Phi_balanced D
    phi[n:, :n] *= a
    return phi


def monodromy_exponents(system: RheoLinear, method: str = "monodromy", steps: int | None = None):
    """Characteristic exponents from the eigenvalues of the monodromy matrix (principal
    logarithm, |Im| <= omega/2). method: "monodromy" (DOP853 reference) or "magnus"
    (``steps`` fixed steps, default :func:`magnus_steps`)."""
    if method == "magnus":
        steps = steps or magnus_steps(system.samples)
        theta = gauss_angles(steps)
        S = system.spectra
        Mg, Cg, Kg = (synthesize(X, theta) for X in (S.mass, S.damping, S.stiffness))
        Phi = magnus_transition(Mg, Cg, Kg, system.period / steps)
    else:
        Phi = monodromy_matrix(system)
    return exponents_from_monodromy(Phi, system.omega, method)


def exponents_from_monodromy(Phi: np.ndarray, omega: float, method: str):
    """FloquetExponents from a monodromy matrix (2n, 2n) at driving speed omega (rad/s)."""
    if not np.isfinite(Phi).all():
        raise ConvergenceError(f"the monodromy matrix ({method}) at omega = {omega:.6g} rad/s is not finite; "
                               "use method='monodromy' (adaptive steps) or check the model's coefficients")
    lam = monodromy_exponent_array(Phi[None], np.array([float(omega)]))[0]
    if np.isnan(lam).any():
        raise ConvergenceError(f"the monodromy matrix ({method}) at omega = {omega:.6g} rad/s is singular: a mode "
                               "decays by more than 1e-308 in one period, so its exponent is not determined; use "
                               "Hill's method (method='dense' or 'sparse') or check the model's damping")
    nan = np.full(lam.size, np.nan)
    return FloquetExponents(float(omega), lam, nan, nan, method)


def monodromy_exponent_array(Phi: np.ndarray, omegas: np.ndarray) -> np.ndarray:
    """Exponents (S, d) from monodromy matrices (S, d, d) at speeds omegas (S,) rad/s: the
    principal logarithms of the multipliers (|Im| <= omega/2), sorted by real then
    imaginary part. A row with a zero multiplier (the monodromy underflowed: a mode decays
    by more than the double range, 1e-308, in one period, so its exponent is not
    determined) is NaN."""
    mu = np.linalg.eigvals(Phi).astype(complex)
    ok = np.all(mu != 0, axis=-1)
    lam = np.full(mu.shape, np.nan + 0j)
    lam[ok] = np.log(mu[ok]) * (np.asarray(omegas, float)[ok, None] / (2 * np.pi))
    return np.take_along_axis(lam, np.lexsort((lam.imag, lam.real), axis=-1), -1)


def integrate(system: RheoLinear, y0, t) -> np.ndarray:
    """Direct solution y = [q, q'] of the forced linear equations from y(0) = y0 (2n,) at
    times t (s, increasing from 0) -> (len(t), 2n)."""
    A_b = first_order_matrix(system)
    t = np.asarray(t, dtype=float)

    def rhs(tt, y):
        A, b = A_b(tt)
        return A @ y + b

    return solve(rhs, (0.0, float(t[-1])), np.asarray(y0, dtype=float), t_eval=t, rtol=RTOL, atol=ATOL).y.T
