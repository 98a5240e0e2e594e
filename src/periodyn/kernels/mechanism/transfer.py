"""The transfer function ``x = F(q)`` of an element model (Schwab & Meijaard 2001, eq. 3,
5-9): Newton solution of the constraint equations ``Phi(x) = b(q)`` (:mod:`.constraints`),
continuation along a path of inputs, and the derivatives of F by implicit
differentiation (solves with the constraint Jacobian factored once, never its inverse).
"""

import numpy as np
from numba import njit

from .constraint_system import allocate_equations, along, contract2, equations
from .lu import factor, inverse_norm1, lu_factor, lu_solve, norm1

@njit(cache=True, inline="always")
def newton(arr, x, b, tol, max_iter):
    """Solve Phi(x) = b in place from the guess x (n_x,). Returns (iterations, residual
    inf-norm, condition flag) with flag 0 = converged, 1 = no convergence,
    2 = singular Jacobian (a zero pivot, or a 1-norm condition number above 1e13
    estimated from the sparse LU factors at the first iteration, :mod:`.lu`). The steps are
    LAPACK solves, so the converged configurations are those of the dense solver bit for bit
    (warm-started callers compare them across calls at round-off)."""
    D, Dx, Dxx, Dxxx, Phi, J = allocate_equations(arr)
    piv = np.empty(x.shape[0], dtype=np.int64)
    res = np.inf
    for it in range(max_iter + 1):
        equations(arr, x, b, D, Dx, Dxx, Dxxx, Phi, J)
        res = np.max(np.abs(Phi - b))
        if res <= tol:
            return it, res, 0
        if it == max_iter or not np.isfinite(res):
            break
        if it == 0:
            LU = J.copy()
            if lu_factor(LU, piv) != 0 or norm1(J) * inverse_norm1(LU, piv) > 1e13:
                return it, res, 2
        x -= np.linalg.solve(J, Phi - b)
    return max_iter, res, 1


@njit(cache=True, inline="always")
def input_jacobian(arr, x):
    """F_q = J^-1 rhs_q at a solved configuration x; (n_x, n_q)."""
    D, Dx, Dxx, Dxxx, Phi, J = allocate_equations(arr)
    equations(arr, x, arr.rhs0, D, Dx, Dxx, Dxxx, Phi, J)
    return np.linalg.solve(J, arr.rhs_q)


@njit(cache=True)
def track(arr, x0, q0, q_targets, tol, max_iter, max_halvings, X, info):
    """Follow the configuration from (x0, q0) through q_targets (p, n_q) sequentially,
    Newton with a first-order predictor and step halving; writes X (p, n_x) and
    info (p, 2) = (iterations, residual). Returns -1 on success or the index of the
    first target that failed (flag in info[j, 0] = -1 singular, -2 no convergence)."""
    x = x0.copy()
    q = q0.copy()
    for j in range(q_targets.shape[0]):
        target = q_targets[j]
        step = target - q
        fraction = 1.0
        done = 0.0
        total_it = 0
        halvings = 0
        while done < 1.0:
            fraction = min(fraction, 1.0 - done)
            dq = fraction * step
            Fq = input_jacobian(arr, x)
            trial = x + Fq @ dq
            b = arr.rhs0 + arr.rhs_q @ (q + dq)
            it, res, flag = newton(arr, trial, b, tol, max_iter)
            total_it += it
            if flag == 0:
                x = trial
                q = q + dq
                done += fraction
                info[j, 1] = res
            else:
                halvings += 1
                if halvings > max_halvings:
                    info[j, 0] = -1.0 if flag == 2 else -2.0
                    info[j, 1] = res
                    return j
                fraction *= 0.5
        X[j] = x
        info[j, 0] = total_it
    return -1


@njit(cache=True, inline="always")
def rates(arr, x, qdot, qddot, v, a, Fd, Fdv, Fda):
    """The part of :func:`motion` that reduced_sample needs (no F_{q^d q^d}): overwrites
    v, a (n_x,), Fd, Fdv, Fda (n_x, n_d) by solves with the constraint Jacobian J,
    factored once (:mod:`.lu`, never its inverse). Returns the element tensors D, Dx, Dxx
    and the factors (LU, piv) of J."""
    n = x.shape[0]
    D, Dx, Dxx, Dxxx, Phi, J = allocate_equations(arr)
    equations(arr, x, arr.rhs0, D, Dx, Dxx, Dxxx, Phi, J)
    LU, piv = factor(J)
    Fq = arr.rhs_q.copy()
    lu_solve(LU, piv, Fq)
    nr = arr.n_input
    nd = Fq.shape[1] - nr
    v[:] = Fq @ qdot
    tmp = np.empty((n, 1))
    contract2(arr, Dxx, v, v, tmp[:, 0])
    lu_solve(LU, piv, tmp)
    a[:] = Fq @ qddot - tmp[:, 0]
    FdT = np.ascontiguousarray(Fq[:, nr:].T)  # (nd, n): rows are the columns of F_q^d
    Fd[:] = FdT.T
    rhs_v = np.empty((n, nd))  # implicit differentiation, one column per dynamic coordinate
    col = np.empty(n)
    for i in range(nd):
        contract2(arr, Dxx, FdT[i], v, col)
        rhs_v[:, i] = -col
    lu_solve(LU, piv, rhs_v)
    Fdv[:] = rhs_v
    FdvT = np.ascontiguousarray(Fdv.T)
    rhs_a = np.empty((n, nd))
    tmp2 = np.empty(n)
    ta = np.empty(n)
    Dv = np.empty(Dxx.shape)
    along(arr, Dxxx, v, Dv)
    for i in range(nd):
        contract2(arr, Dv, FdT[i], v, col)
        contract2(arr, Dxx, FdT[i], a, ta)
        contract2(arr, Dxx, FdvT[i], v, tmp2)
        rhs_a[:, i] = -(col + ta + 2.0 * tmp2)
    lu_solve(LU, piv, rhs_a)
    Fda[:] = rhs_a
    return D, Dx, Dxx, LU, piv


@njit(cache=True)
def motion(arr, x, qdot, qddot, v, a, Fd, Fdv, Fdd, Fda):
    """Transfer-function derivatives at a solved configuration x for input rates qdot,
    qddot (n_q,) (all of q, dynamic included). Overwrites
    v = F_q qdot, a = F_q qddot + F_qq qdot qdot (n_x,), Fd = F_q^d (n_x, n_d),
    Fdv = F_{q^d q} qdot (n_x, n_d), Fdd = F_{q^d q^d} (n_x, n_d, n_d),
    Fda = F_{q^d q} qddot + F_{q^d q q} qdot qdot (n_x, n_d)."""
    n = x.shape[0]
    nd = Fd.shape[1]
    D, Dx, Dxx, LU, piv = rates(arr, x, qdot, qddot, v, a, Fd, Fdv, Fda)
    FdT = np.ascontiguousarray(Fd.T)
    rhs_dd = np.empty((n, nd * nd))
    col = np.empty(n)
    for i in range(nd):
        for j in range(i, nd):
            contract2(arr, Dxx, FdT[i], FdT[j], col)
            rhs_dd[:, i * nd + j] = -col
            rhs_dd[:, j * nd + i] = -col
    lu_solve(LU, piv, rhs_dd)
    Fdd[:] = rhs_dd.reshape(n, nd, nd)
    return D, Dx, Dxx
