"""Linearization of a DAE/ODE about a periodic orbit, reduced to independent coordinates.

The perturbation of an orbit obeys the linearized DAE
``M dq'' + C dq' + K dq + Phi_q^T dlam = 0``, ``Phi_q dq = 0`` with
``C = -df/dq'``, ``K = -df/dq + sum lam_k Phi_k,qq (+ d(M q'')/dq)``. Coordinate
partitioning (dependent coordinates v with ``Phi_v`` invertible along the whole orbit)
gives the null-space basis ``N(t) = [I; -Phi_v^-1 Phi_u]`` (in the original order), and
``dq = N z`` reduces it to the ODE in the r = n - m independent coordinates

    Mb z'' + Cb z' + Kb z = 0,  Mb = N^T M N,  Cb = N^T (2 M N' + C N),
    Kb = N^T (M N'' + C N' + K N),

with N', N'' by spectral differentiation of the samples of N. The result is the same
``periodyn.RheoLinear`` the rheo-linear path uses (omega = the orbit's base frequency
omega/nu, so its period is the orbit period), so Hill (dense/sparse), Magnus and the
monodromy reference of the stability registry (:mod:`periodyn.stability.methods`) all give
the orbit's Floquet exponents (:func:`orbit_exponents`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from ..errors import ConvergenceError
from ..stability.floquet import FloquetExponents
from ..stability.methods import DeferredOperator, method_named, spectra_operator
from ..numerics.spectra import fourier_coefficients, to_samples
from ..system import RheoLinear

__all__ = ["OrbitLinearization", "linearize_orbit", "orbit_exponents"]


@dataclass(frozen=True, eq=False)
class OrbitLinearization:
    """Perturbation equations of one orbit in independent coordinates.

    rheo: RheoLinear with r coordinates, samples at t_j = period j / p, force zero;
    basis: N (p, n, r) with dq = N z at the same times; independent: (r,) indices of the
    independent coordinates in q.
    """

    rheo: RheoLinear
    basis: np.ndarray
    independent: np.ndarray

    @property
    def r(self) -> int:
        return self.basis.shape[2]


def _partition(Pq: np.ndarray) -> np.ndarray:
    """Dependent coordinate indices (m,) with the best worst-case conditioning of Phi_v
    over the samples; candidates from pivoted QR at a few samples."""
    p, m, n = Pq.shape
    best, best_cond = None, np.inf
    candidates = dict.fromkeys(tuple(np.sort(sla.qr(Pq[j], pivoting=True, mode="r")[1][:m]))
                               for j in np.unique(np.linspace(0, p - 1, min(p, 8)).astype(int)))
    for dep in candidates:  # a partition found at several samples is checked once
        dep = np.array(dep)
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


def linearize_orbit(system, t, q, qd, qdd, lam, omega, params, period) -> OrbitLinearization:
    """Reduced perturbation equations from orbit samples at p equidistant times t (p,)
    over one ``period`` (s): q, qd, qdd (p, n), lam (p, m); omega: driving frequency (rad/s)."""
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
    Mb = NT @ Mt @ N
    Cb = NT @ (2 * Mt @ N1 + Ct @ N)
    Kb = NT @ (Mt @ N2 + Ct @ N1 + Kt @ N)
    names = tuple(system.coordinate_names[i] for i in ind)
    rheo = RheoLinear.from_samples(Mb, Cb, Kb, np.zeros((p, n - m)), 2 * np.pi / period, coordinate_names=names)
    return OrbitLinearization(rheo, np.ascontiguousarray(N), ind)


def orbit_exponents(lin: OrbitLinearization, method: str = "magnus", harmonics: int | None = None):
    """Floquet exponents (FloquetExponents, 2r of them, over the orbit period) of an orbit.

    method: a stability method of :mod:`periodyn.stability.methods`: "magnus" (4th-order
    Magnus, max(128, 4p) steps), "monodromy" (DOP853 reference), "hill" (Hill's method,
    dense or sparse by estimated cost), "dense", "sparse", "auto", or a registered one;
    harmonics: Hill harmonics (default half of what the p samples resolve, at least 4).
    """
    rheo = lin.rheo
    entry = method_named(method)
    if lin.r == 0:
        return FloquetExponents.from_multipliers(np.zeros(0), rheo.omega, method)
    S = rheo.spectra
    K = (S.mass.shape[0] - 1) // 2
    m = harmonics or max(K // 2, 4)
    op = None
    if entry.operator:
        op = DeferredOperator(m, lin.r, lambda: spectra_operator(S.mass, S.damping, S.stiffness, rheo.omega, m))
        op = op if entry.deferred else op()
    return entry.exponents(rheo, op, steps=max(128, 4 * rheo.samples))
