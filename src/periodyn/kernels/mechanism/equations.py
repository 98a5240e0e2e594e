"""The full non-linear reduced equations (4) of an element model at many states at once
(Schwab & Meijaard 2001, eq. 4): ``M̄(q) q̈^d + F_dᵀ (M F_qq q̇ q̇ - f) = 0`` solved for the
dynamic accelerations, with their Jacobians by implicit differentiation.

Per state k: the configuration x = F(q) by Newton from a warm start (a solved
configuration nearby, updated in place), then :func:`assembly.reduced_sample` at the
state's rates with q̈^d = 0 (and the prescribed q̈^r, with the state's nodal loads)
gives M̄ and the residual R0 = f^d, so q̈^d = -M̄⁻¹ R0. The
residual R(q, q̇, q̈) is affine in q̈^d with slope M̄, so at the solution
``d q̈^d / d q^d = -M̄⁻¹ K̄`` and ``d q̈^d / d q̇^d = -M̄⁻¹ C̄`` with K̄, C̄ of
reduced_sample evaluated at the actual accelerations (a second pass, only when asked).
"""

import numpy as np
from numba import njit

from . import assembly, constraint_system, transfer


@njit(cache=True)
def _state(arr, x, qdot, qddot, load, Mb, Cb, Kb, fd):
    """reduced_sample at x (M̄, C̄, K̄, f^d) with scratch transfer-function arrays."""
    n = x.shape[0]
    nd = Mb.shape[0]
    Fd = np.empty((n, nd))
    Fdv = np.empty((n, nd))
    Fda = np.empty((n, nd))
    assembly.reduced_sample(arr, x, qdot, qddot, load, Mb, Cb, Kb, fd, Fd, Fdv, Fda)


@njit(cache=True)
def _configuration(arr, x, q, xs, qs, Fs, tol, max_iter, D, Dx, Dxx, Dxxx, Phi, J):
    """x = F(q) by Newton from the predictor xs + Fs (q - qs) of a solved warm start
    (xs at qs with F_q = Fs); on success the tensors and J are those at x. Returns the
    iterations (>= 0), or -1 when Newton did not converge in max_iter, and the residual."""
    b = arr.rhs0 + arr.rhs_q @ q
    x[:] = xs + Fs @ (q - qs)
    res = np.inf
    for it in range(max_iter + 1):
        constraint_system.equations(arr, x, b, D, Dx, Dxx, Dxxx, Phi, J)
        res = np.max(np.abs(Phi - b))
        if res <= tol:
            return it, res
        if it == max_iter or not np.isfinite(res):
            break
        x -= np.linalg.solve(J, Phi - b)
    return -1, res


@njit(cache=True)
def _acceleration(arr, x, qdot, qddot, load, D, Dx, Dxx, J, Fq, acc):
    """q̈^d (n_d,) at a solved configuration x (tensors D, Dx, Dxx and J at x) for rates
    qdot (n_q,), accelerations qddot (n_q,) whose dynamic part is zero in F_dᵀ M a, and
    nodal loads ``load`` (n_x,) besides the constant ones; overwrites Fq = F_q (n_x, n_q)."""
    n = x.shape[0]
    nd = acc.shape[0]
    nr = qdot.shape[0] - nd
    Fq[:] = np.linalg.solve(J, arr.rhs_q)
    v = Fq @ qdot
    conv = np.empty(n)
    constraint_system.contract2(arr, Dxx, v, v, conv)
    a = Fq @ qddot - np.linalg.solve(J, conv)
    M = np.empty((n, n))
    r = np.empty(n)
    C = np.empty((n, n))
    K = np.empty((n, n))
    assembly.nodal_arrays(arr, x, v, a, D, Dx, Dxx, M, r, C, K)
    r -= load
    Fd = np.ascontiguousarray(Fq[:, nr:])
    acc[:] = np.linalg.solve(Fd.T @ (M @ Fd), -(Fd.T @ r))


@njit(cache=True)
def accelerations(arr, Q, Qdot, Qddot, loads, X, Qx, FQ, tol, max_iter, max_halvings, jacobians, acc, Gq, Gv, info):
    """Dynamic accelerations of the states Q, Qdot (b, n_q) (q = [q^r, q^d]) with the
    prescribed accelerations Qddot (b, n_q) (the dynamic part must be zero) and nodal
    loads (b, n_x) besides the model's constant ones.

    X (b, n_x), FQ (b, n_x, n_q): solved configurations at Qx (b, n_q) and their F_q on
    entry (warm starts), overwritten by those at Q (Qx updated). Writes acc (b, n_d); if
    jacobians, Gq = d acc / d q^d and Gv = d acc / d q̇^d (b, n_d, n_d). info (b, 2):
    Newton iterations and residual; iterations -1 (singular) or -2 (no convergence) on
    failure, and then that state's outputs are not written."""
    b, n = X.shape
    nq = Q.shape[1]
    nd = acc.shape[1]
    nr = nq - nd
    for k in range(b):
        D, Dx, Dxx, Dxxx, Phi, J = constraint_system.allocate_equations(arr)
        x = np.empty(n)
        it, res = _configuration(arr, x, Q[k], X[k], Qx[k], FQ[k], tol, max_iter, D, Dx, Dxx, Dxxx, Phi, J)
        if it < 0:  # far from the warm start: continuation with step halving
            xk = np.empty((1, n))
            ik = np.zeros((1, 2))
            if transfer.track(arr, X[k].copy(), Qx[k].copy(), Q[k:k + 1], tol, max_iter, max_halvings, xk, ik) >= 0:
                info[k, 0] = ik[0, 0]
                info[k, 1] = ik[0, 1]
                continue
            x[:] = xk[0]
            it, res = _configuration(arr, x, Q[k], xk[0], Q[k], FQ[k], tol, max_iter, D, Dx, Dxx, Dxxx, Phi, J)
            if it < 0:
                info[k, 0] = -2.0
                info[k, 1] = res
                continue
        info[k, 0] = it
        info[k, 1] = res
        X[k] = x
        Qx[k] = Q[k]
        _acceleration(arr, x, Qdot[k], Qddot[k], loads[k], D, Dx, Dxx, J, FQ[k], acc[k])
        if jacobians:
            Mb = np.empty((nd, nd))
            Cb = np.empty((nd, nd))
            Kb = np.empty((nd, nd))
            fd = np.empty(nd)
            qddot = Qddot[k].copy()
            qddot[nr:] = acc[k]
            _state(arr, x, Qdot[k], qddot, loads[k], Mb, Cb, Kb, fd)
            Gq[k] = -np.linalg.solve(Mb, Kb)
            Gv[k] = -np.linalg.solve(Mb, Cb)
