"""Fixed-step trapezoidal rule for q'' = a(t, q, q') with its discrete variational
equations, entirely in Numba.

State y = (q, q') (2n,), f(t, y) = (q', a). One step of size h solves

    G(y1, y0) = y1 - y0 - h/2 (f(t0, y0) + f(t1, y1)) = 0

by simplified Newton: the iteration matrix I - h/2 J0 uses the analytic Jacobian
J = df/dy = [[0, I], [a_q, a_q']] at the step's start, and each iteration evaluates the
accelerations only (without their Jacobians, the costly part of an element model); a
converged step ends with one evaluation with Jacobians at y1, so J1 is the Jacobian at
the converged state. The derivative of the discrete map y0 -> y1 follows from the same
Jacobians, S1 = (I - h/2 J1)⁻¹ (I + h/2 J0) S0: the product over one period is the exact
monodromy matrix of the discrete one-period map (no finite differences).

The right-hand side is ``evaluate(data, t, q, qd, acc, Gq, Gv, jacobians) -> bool``
(False: no acceleration at that state; Gq, Gv written when ``jacobians``), chosen at
compile time by the kind of ``data`` (so the kernels are cached like any other): a
17-tuple for element models (:func:`element_evaluate`, :mod:`periodyn.kernels.mechanism.equations`),
a 4-tuple for rheo-linear systems (:func:`linear_evaluate`).
"""

import numpy as np
from numba import njit
from numba.extending import overload

from ..mechanism import equations


@njit(cache=True)
def _jacobian(Gq, Gv, J):
    """J = [[0, I], [Gq, Gv]] (2n, 2n) in place."""
    n = Gq.shape[0]
    J[:] = 0.0
    for i in range(n):
        J[i, n + i] = 1.0
    J[n:, :n] = Gq
    J[n:, n:] = Gv


@njit(cache=True)
def _step(data, t1, h, y0, f0, J0, y1, f1, J1, tol, max_iter):
    """Simplified Newton for y1 (predicted on entry) of one trapezoidal step from (y0, f0)
    with the iteration matrix I - h/2 J0 of the step's start (accelerations only per
    iteration); on success f1 = f(t1, y1) and J1 the Jacobian at y1 (one evaluation with
    Jacobians). Returns the iterations (>= 0), -1 when a state has no acceleration (or
    its Jacobian is not finite), -2 when the iteration did not converge in max_iter."""
    n2 = y0.shape[0]
    n = n2 // 2
    acc = np.empty(n)
    Gq = np.empty((n, n))
    Gv = np.empty((n, n))
    A = np.eye(n2) - 0.5 * h * J0
    for it in range(max_iter + 1):
        if not evaluate(data, t1, y1[:n], y1[n:], acc, Gq, Gv, False):
            return -1
        f1[:n] = y1[n:]
        f1[n:] = acc
        G = y1 - y0 - 0.5 * h * (f0 + f1)
        res = np.max(np.abs(G))
        if not np.isfinite(res):
            return -2
        if res <= tol * (1.0 + np.max(np.abs(y1))):
            if not evaluate(data, t1, y1[:n], y1[n:], acc, Gq, Gv, True):
                return -1
            f1[n:] = acc
            _jacobian(Gq, Gv, J1)
            return it if np.all(np.isfinite(J1)) else -1
        if it == max_iter:
            return -2
        y1 -= np.linalg.solve(A, G)
    return -2


@njit(cache=True)
def period_map(data, y0, t0, T, steps, tol, max_iter, Y, S, counts):
    """Integrate from y0 (2n,) at t0 over T (s) in ``steps`` trapezoidal steps.

    Writes Y (steps + 1, 2n): states at t0 + k T / steps, S (2n, 2n): d y(T) / d y0 of the
    discrete map, counts (2,): evaluations and Newton updates. Returns ``steps`` on
    success, else the index of the failed step (its state has no acceleration, a
    Jacobian that is not finite, or Newton did not converge)."""
    n2 = y0.shape[0]
    n = n2 // 2
    h = T / steps
    acc = np.empty(n)
    Gq = np.empty((n, n))
    Gv = np.empty((n, n))
    J0 = np.empty((n2, n2))
    J1 = np.empty((n2, n2))
    eye = np.eye(n2)
    counts[:] = 0
    Y[0] = y0
    if not evaluate(data, t0, y0[:n], y0[n:], acc, Gq, Gv, True):
        return 0
    counts[0] += 1
    f0 = np.empty(n2)
    f0[:n] = y0[n:]
    f0[n:] = acc
    _jacobian(Gq, Gv, J0)
    if not np.all(np.isfinite(J0)):
        return 0
    f1 = np.empty(n2)
    y1 = np.empty(n2)
    S[:] = eye
    for k in range(steps):
        yk = Y[k]
        y1[:n] = yk[:n] + h * yk[n:] + 0.5 * h * h * f0[n:]  # Taylor predictor
        y1[n:] = yk[n:] + h * f0[n:]
        it = _step(data, t0 + (k + 1) * h, h, yk, f0, J0, y1, f1, J1, tol, max_iter)
        if it < 0:
            return k
        counts[0] += it + 2
        counts[1] += it
        S[:] = np.linalg.solve(eye - 0.5 * h * J1, (eye + 0.5 * h * J0) @ S)
        Y[k + 1] = y1
        f0[:] = f1
        J0[:] = J1
    return steps


@njit(cache=True)
def element_evaluate(data, t, q, qd, acc, Gq, Gv, jacobians):
    """Accelerations q̈^d and their Jacobians of an element model at one state (q^d, q̇^d)
    at time t, inputs q^r = rates omega t (constant speed). data: (arrays, rates (n_r,),
    omega, Q, Qd, Qdd (1, n_q; Qdd zero), loads (1, n_x; zero), X (1, n_x), Qx (1, n_q),
    FQ (1, n_x, n_q) warm starts (updated in place), tol, max_iter, max_halvings, scratch
    acc (1, n_d), Gq, Gv (1, n_d, n_d), info (1, 2))."""
    arr, rates, omega, Q, Qd, Qdd, loads, X, Qx, FQ, ctol, max_iter, max_halvings, a, A, B, info = data
    nr = rates.shape[0]
    for i in range(nr):
        Q[0, i] = omega * t * rates[i]
        Qd[0, i] = omega * rates[i]
    Q[0, nr:] = q
    Qd[0, nr:] = qd
    equations.accelerations(arr, Q, Qd, Qdd, loads, X, Qx, FQ, ctol, max_iter, max_halvings, jacobians, a, A, B, info)
    if info[0, 0] < 0:
        return False
    acc[:] = a[0]
    if jacobians:
        Gq[:] = A[0]
        Gv[:] = B[0]
    return True


@njit(cache=True)
def linear_evaluate(data, t, q, qd, acc, Gq, Gv, jacobians):
    """q'' = r(t) - P(t) q' - Q(t) q of a rheo-linear system; data: (omega, P, Q (2K+1, n,
    n), r (2K+1, n)) two-sided spectra of P = M⁻¹C, Q = M⁻¹K, r = M⁻¹f over omega t."""
    omega, P, Q, r = data
    K = (P.shape[0] - 1) // 2
    Gq[:] = 0.0
    Gv[:] = 0.0
    acc[:] = 0.0
    for k in range(-K, K + 1):
        e = np.exp(1j * k * omega * t)
        Gv -= (P[k + K] * e).real
        Gq -= (Q[k + K] * e).real
        acc += (r[k + K] * e).real
    acc += Gv @ qd + Gq @ q
    return True


def evaluate(data, t, q, qd, acc, Gq, Gv, jacobians):
    """Right-hand side by the kind of data (module docstring)."""


@overload(evaluate)
def _evaluate(data, t, q, qd, acc, Gq, Gv, jacobians):
    if len(data) == 17:
        return lambda data, t, q, qd, acc, Gq, Gv, jacobians: element_evaluate(data, t, q, qd, acc, Gq, Gv, jacobians)
    if len(data) == 4:
        return lambda data, t, q, qd, acc, Gq, Gv, jacobians: linear_evaluate(data, t, q, qd, acc, Gq, Gv, jacobians)
    return None
