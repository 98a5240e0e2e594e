"""Stability of periodic DAE solutions through independent coordinates (Floquet).

The perturbation of an orbit obeys the linearized DAE
``M dq'' + C dq' + K dq + Phi_q^T dlam = 0``, ``Phi_q dq = 0`` with
``C = -df/dq'``, ``K = -df/dq + sum lam_k Phi_k,qq (+ d(M q'')/dq)``. Coordinate
partitioning (dependent coordinates v with ``Phi_v`` invertible along the whole orbit)
gives the null-space basis ``N(t) = [I; -Phi_v^-1 Phi_u]`` (in the original order), and
``dq = N z`` reduces it to the ODE in the r = n - m independent coordinates

    Mb z'' + Cb z' + Kb z = 0,  Mb = N^T M N,  Cb = N^T (2 M N' + C N),
    Kb = N^T (M N'' + C N' + K N),

with N', N'' by spectral differentiation of the samples of N. Its Floquet multipliers
(2r of them) come from the monodromy matrix (4th-order Magnus integrator over one period,
coefficients interpolated trigonometrically) or from Hill's method
(``periodyn.hill.hill_exponents``, exponents -> multipliers ``exp(s T)``).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ..errors import ConvergenceError, InputError
from ..spectra import fourier_coefficients, to_samples
from ..timedomain import gauss_angles, magnus_transition

__all__ = ["ReducedLinearization", "reduce_linearization", "propagate", "monodromy", "floquet_multipliers",
           "ihb_multipliers"]


class ReducedLinearization:
    """Independent-coordinate perturbation equations sampled over one orbit.

    mass/damping/stiffness: (p, r, r) samples at t_j = period j / p; basis: N (p, n, r);
    independent: indices of the independent coordinates (r,); period: s.
    """

    def __init__(self, mass, damping, stiffness, basis, independent, period):
        self.mass, self.damping, self.stiffness = mass, damping, stiffness
        self.basis, self.independent, self.period = basis, independent, float(period)

    @property
    def r(self) -> int:
        return self.mass.shape[1]


def _partition(Pq: np.ndarray) -> np.ndarray:
    """Dependent coordinate indices (m,) with the best worst-case conditioning of Phi_v
    over the samples; candidates from pivoted QR at a few samples."""
    p, m, n = Pq.shape
    best, best_cond = None, np.inf
    for j in np.unique(np.linspace(0, p - 1, min(p, 8)).astype(int)):
        piv = sla.qr(Pq[j], pivoting=True, mode="r")[1]
        dep = np.sort(piv[:m])
        cond = np.max(np.linalg.cond(Pq[:, :, dep]))
        if cond < best_cond:
            best, best_cond = dep, cond
    if not np.isfinite(best_cond) or best_cond > 1e10:
        raise ConvergenceError(f"no coordinate partition keeps Phi_v invertible along the orbit (condition {best_cond:.3g}); "
                               "the constraints are redundant or the mechanism passes a singular position")
    return best


def _spectral_derivatives(N: np.ndarray, Om: float):
    c = fourier_coefficients(N)
    K = (c.shape[0] - 1) // 2
    ik = (1j * Om * np.arange(-K, K + 1)).reshape((-1,) + (1,) * (N.ndim - 1))
    p = N.shape[0]
    return to_samples(ik * c, p), to_samples(ik * ik * c, p)


def reduce_linearization(system, t, q, qd, qdd, lam, omega, params, period) -> ReducedLinearization:
    """Reduced perturbation equations from orbit samples at p equidistant times t (p,)
    over one ``period``: q, qd, qdd (p, n), lam (p, m)."""
    P = system.parameters if params is None else params
    n, m = system.n, system.m
    p = q.shape[0]
    Mt = np.asarray(system.mass(q))
    Kf, Cf = system.force_jacobians(q, qd, t, omega, P)
    Kt, Ct = -Kf, -Cf
    if system.mass_jacobian is not None:
        Kt = Kt + system.mass_jacobian(q, qdd)
    if m:
        Kt = Kt + system.constraint_hessian(q, lam, t, omega, P)
        Pq = system.constraint_jacobian(q, t, omega, P)
        dep = _partition(Pq)
        ind = np.setdiff1d(np.arange(n), dep)
        N = np.zeros((p, n, n - m))
        N[:, ind, np.arange(n - m)] = 1.0
        N[:, dep, :] = -np.linalg.solve(Pq[:, :, dep], Pq[:, :, ind])
        N1, N2 = _spectral_derivatives(N, 2 * np.pi / period)
    else:
        ind = np.arange(n)
        N = np.broadcast_to(np.eye(n), (p, n, n))
        N1 = N2 = np.zeros((p, n, n))
    NT = np.swapaxes(N, 1, 2)
    MN = Mt @ N
    Mb = NT @ MN
    Cb = NT @ (2 * Mt @ N1 + Ct @ N)
    Kb = NT @ (Mt @ N2 + Ct @ N1 + Kt @ N)
    return ReducedLinearization(Mb, Cb, Kb, np.ascontiguousarray(N), ind, period)


def _interpolate(samples: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Trigonometric interpolation of equidistant samples (p, ...) at angles theta (s,)."""
    c = fourier_coefficients(samples)
    K = (c.shape[0] - 1) // 2
    arg = np.outer(theta, np.arange(-K, K + 1))
    cf = c.reshape(c.shape[0], -1)
    return (np.cos(arg) @ cf.real - np.sin(arg) @ cf.imag).reshape((len(theta),) + samples.shape[1:])


def propagate(red: ReducedLinearization, t0: float, t1: float, steps: int) -> np.ndarray:
    """Transition matrix (2r, 2r) of ``y' = A(t) y``, ``y = (z, z')``, from t0 to t1 (s) by
    the 4th-order Magnus integrator of :func:`periodyn.timedomain.magnus_transition`
    (robust for stiff oscillatory modes); coefficients by trigonometric interpolation."""
    theta = gauss_angles(steps, 2 * np.pi * t0 / red.period, 2 * np.pi * t1 / red.period)
    Ms, Cs, Ks = (_interpolate(a, theta) for a in (red.mass, red.damping, red.stiffness))
    return magnus_transition(Ms, Cs, Ks, (t1 - t0) / steps)


def monodromy(red: ReducedLinearization, steps: int | None = None) -> np.ndarray:
    """Monodromy matrix (2r, 2r) over one period; steps default 4 per orbit sample, >= 128."""
    return propagate(red, 0.0, red.period, steps or max(128, 4 * red.mass.shape[0]))


def floquet_multipliers(red: ReducedLinearization, method: str = "monodromy", harmonics: int | None = None) -> np.ndarray:
    """Floquet multipliers (2r,) of the reduced equations, sorted by decreasing |mu|.

    method "monodromy" (Magnus integration) or "hill" (``periodyn.hill.hill_exponents``
    with ``harmonics`` Hill harmonics, default as many as the samples resolve / 2)."""
    if red.r == 0:
        return np.zeros(0, complex)
    if method == "monodromy":
        mu = np.linalg.eigvals(monodromy(red))
    elif method == "hill":
        from ..hill import hill_exponents
        Om = 2 * np.pi / red.period
        K = (red.mass.shape[0] - 1) // 2
        res = hill_exponents(fourier_coefficients(red.mass), fourier_coefficients(red.damping),
                             fourier_coefficients(red.stiffness), Om, harmonics or max(K // 2, 4))
        mu = np.exp(np.asarray(res.exponents) * red.period)
    else:
        raise InputError(f"stability method must be 'monodromy' or 'hill', got {method!r}")
    return mu[np.argsort(-np.abs(mu), kind="stable")]


def ihb_multipliers(prob, X, omega, params=None, method="monodromy") -> np.ndarray:
    """Floquet multipliers of the IHB orbit X of an ``IHBProblem``."""
    t, q, qd, qdd, lam = prob.time_samples(X, omega)
    red = reduce_linearization(prob.system, t, q, qd, qdd, lam, omega, params, 2 * np.pi * prob.nu / omega)
    return floquet_multipliers(red, method)
