"""Transient towards the periodic solution (Schwab & Meijaard eq. 19-24).

The homogeneous equations ``y' = A(t) y`` (y = [q, q'], A from P = M^-1 C, Q = M^-1 K)
are written on the eigenvectors Y of the mean matrix A0 (J0 = Y^-1 A0 Y diagonal) and
with slowly varying amplitudes ``z = exp(J0 t) a``. First-order averaging keeps only the
diagonal of ``J~(t) = Y^-1 (A(t) - A0) Y``:

    a_i(t) = a_i(0) exp(int_0^t J~_ii dtau),

whose integral is exact for the Fourier series of J~_ii.

Validity: the eigenvalues of A0 must be distinct, damped, with imaginary parts well
above omega and well separated (the off-diagonal terms then average out), and the
periodic part of A small against the diagonal of J0 -- typically a stiff structure driven
well below its first eigenfrequency, as the slider-crank rod. Near parametric resonances
or for slow modes use method="integrate" (direct solution of the linear equations).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import InputError
from .periodic import PeriodicSolution
from .system import RheoLinear
from .stability.monodromy import integrate

__all__ = ["Transient", "transient"]


@dataclass(frozen=True, eq=False)
class Transient:
    """Complete solution on times t (s): q, qd (len(t), n) = periodic + transient parts;
    periodic_q (len(t), n); outputs (len(t), n_out) of the complete solution; method."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    periodic_q: np.ndarray
    outputs: np.ndarray
    periodic_outputs: np.ndarray
    method: str


def _output_samples(system: RheoLinear, t: np.ndarray, q: np.ndarray) -> np.ndarray:
    from .numerics.spectra import synthesize

    G = synthesize(system.spectra.outputs, system.omega * t)  # (len(t), n_out, n)
    return np.einsum("toj,tj->to", G, q)


def _averaged_homogeneous(system: RheoLinear, y0: np.ndarray, t: np.ndarray) -> np.ndarray:
    n = system.n
    S = system.inverse_mass_spectra
    K = (S.damping.shape[0] - 1) // 2
    Ak = np.zeros((2 * K + 1, 2 * n, 2 * n), dtype=complex)
    Ak[:, n:, :n] = -S.stiffness
    Ak[:, n:, n:] = -S.damping
    Ak[K, :n, n:] = np.eye(n)
    J0, Y = np.linalg.eig(Ak[K])
    gaps = np.abs(J0[:, None] - J0[None, :])
    np.fill_diagonal(gaps, np.inf)
    if gaps.min() < 1e-9 * max(1.0, np.abs(J0).max()):
        raise InputError("averaging needs distinct eigenvalues of the mean system matrix A0; use method='integrate'")
    Yinv = np.linalg.inv(Y)
    d = np.einsum("ij,kjl,li->ki", Yinv, Ak, Y)  # diagonal of Y^-1 A_k Y, (2K+1, 2n)
    k = np.arange(-K, K + 1)
    w = system.omega
    nz = k != 0
    phase = np.exp(1j * np.outer(t, k[nz]) * w) - 1.0  # (len(t), 2K)
    integral = phase @ (d[nz] / (1j * k[nz, None] * w))  # (len(t), 2n)
    a = np.exp(np.outer(t, J0) + integral) * (Yinv @ y0)[None, :]
    return (a @ Y.T).real


def transient(system: RheoLinear, periodic: PeriodicSolution, y0, t, *, method: str = "averaging") -> Transient:
    """Complete solution from initial state y0 = [q(0), q'(0)] (2n,) at times t (s, from 0).

    method="averaging": periodic solution + averaged homogeneous transient (eq. 24);
    method="integrate": direct integration of the linear equations (reference).
    """
    n = system.n
    y0 = np.asarray(y0, dtype=float).reshape(-1)
    if y0.shape != (2 * n,):
        raise InputError(f"y0 must hold q(0) and q'(0): shape ({2 * n},), got {np.shape(y0)}")
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size == 0 or t[0] < 0 or np.any(np.diff(t) <= 0):
        raise InputError("t must be a 1-D increasing array of times >= 0 in seconds")
    qp, qdp = periodic(t), periodic.velocity(t)
    if method == "averaging":
        yp0 = np.concatenate([periodic(0.0)[0], periodic.velocity(0.0)[0]])
        y_tr = _averaged_homogeneous(system, y0 - yp0, t)
        q, qd = qp + y_tr[:, :n], qdp + y_tr[:, n:]
    elif method == "integrate":
        y = integrate(system, y0, t if t[0] == 0 else np.concatenate([[0.0], t]))[-t.size:]
        q, qd = y[:, :n], y[:, n:]
    else:
        raise InputError(f"unknown transient method {method!r}; choose 'averaging' or 'integrate'")
    return Transient(t, q, qd, qp, _output_samples(system, t, q), _output_samples(system, t, qp), method)
