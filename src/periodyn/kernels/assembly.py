"""Generic assembly over element families: constraint equations, Newton solution of the
transfer function ``x = F(q)``, its derivatives by implicit differentiation, nodal
inertia/elastic arrays and the reduced linearized equations (eq. 5, 7, 9, 10 of
Schwab & Meijaard 2001) per sample, parallel over samples with ``prange``.

Nothing here assumes two dimensions: a family is dispatched by its integer id to its
deformation / inertia kernel, and local arrays are as wide as the widest family of the
model (the widths of ``dofs`` and ``modes``, see :mod:`.layout`).

Constraint equations ``Phi(x) = b(q) = rhs0 + rhs_q q`` with one row per fixed,
prescribed or dynamic nodal coordinate (``Phi = x_i``) and per rigid, prescribed or
flexible deformation mode (``Phi = D_k(x)``); ``q = [q^r, q^d]``.
"""

from collections import namedtuple

import numpy as np
from numba import njit, prange

from .layout import (FAMILY_EULER_NORMALIZATION, FAMILY_PLANAR_BEAM, FAMILY_PLANAR_HINGE, FAMILY_PLANAR_TRUSS,
                     FAMILY_RIGID_BODY, FAMILY_RIGID_LINK, FAMILY_SPATIAL_BEAM, FAMILY_SPATIAL_HINGE,
                     FAMILY_SPATIAL_TRUSS)
from . import planar_beam, planar_hinge, planar_truss, rigid_body, spatial_beam, spatial_joints, spatial_truss
from .elastic import add_elastic

ModelArrays = namedtuple("ModelArrays", [
    "family",       # (ne,) int64 family id
    "dofs",         # (ne, n_dof) int64 global nodal-coordinate index, -1 padded
    "ndof",         # (ne,) int64
    "par",          # (ne, n_par) float geometric parameters of the family, zero padded
    "modes",        # (ne, n_mode) int64 global mode index, -1 padded
    "nmode",        # (ne,) int64
    "stiffness",    # (ne, n_mode, n_mode) Kelvin-Voigt S (flexible/free modes only)
    "damping",      # (ne, n_mode, n_mode) Kelvin-Voigt S_d, s * S units
    "stress0",      # (ne, n_mode) constant stress sigma_0 of free/flexible modes (N, N m)
    "ipar",         # (ne, n_ipar) float inertia parameters, layout per family module, zero padded
    "gravity",      # (dim,) m/s^2
    "mode_row",     # (n_modes,) int64 constraint row or -1 (free mode)
    "coord_row",    # (n_x,) int64 constraint row or -1 (dependent coordinate)
    "rhs0",         # (n_x,) constant part of b
    "rhs_q",        # (n_x, n_q) b = rhs0 + rhs_q q
    "n_input",      # int, q^r = q[:n_input], q^d = q[n_input:]
    "nodal_mass",   # (n_x,) point masses / rotational inertias, kg or kg m^2
    "nodal_force",  # (n_x,) constant forces (N) / torques (N m) incl. gravity on point masses
])


@njit(cache=True)
def element_tensors(arr, x, D, Dx, Dxx, Dxxx):
    """Deformation modes and derivatives of every element at nodal coordinates x (n_x,):
    overwrites D (ne, n_mode), Dx (ne, n_mode, n_dof), Dxx (..., n_dof),
    Dxxx (..., n_dof, n_dof)."""
    xe = np.zeros(arr.dofs.shape[1])
    for e in range(arr.family.shape[0]):
        nd = arr.ndof[e]
        for a in range(nd):
            xe[a] = x[arr.dofs[e, a]]
        fam = arr.family[e]
        if fam == FAMILY_PLANAR_BEAM:
            planar_beam.deformation(xe, arr.par[e], D[e], Dx[e], Dxx[e], Dxxx[e])
        elif fam == FAMILY_PLANAR_TRUSS:
            planar_truss.deformation(xe, arr.par[e], D[e], Dx[e], Dxx[e], Dxxx[e])
        elif fam == FAMILY_PLANAR_HINGE:
            planar_hinge.deformation(xe, arr.par[e], D[e], Dx[e], Dxx[e], Dxxx[e])
        elif fam == FAMILY_EULER_NORMALIZATION:
            spatial_joints.normalization(xe, arr.par[e], D[e], Dx[e], Dxx[e], Dxxx[e])
        elif fam == FAMILY_SPATIAL_TRUSS:
            spatial_truss.deformation(xe, arr.par[e], D[e], Dx[e], Dxx[e], Dxxx[e])
        elif fam == FAMILY_SPATIAL_HINGE:
            spatial_joints.hinge(xe, arr.par[e], D[e], Dx[e], Dxx[e], Dxxx[e])
        elif fam == FAMILY_RIGID_LINK:
            spatial_joints.rigid_link(xe, arr.par[e], D[e], Dx[e], Dxx[e], Dxxx[e])
        elif fam == FAMILY_SPATIAL_BEAM:
            spatial_beam.deformation(xe, arr.par[e], D[e], Dx[e], Dxx[e], Dxxx[e])


@njit(cache=True)
def allocate_tensors(arr):
    """Zeroed element tensors D, Dx, Dxx, Dxxx for :func:`element_tensors`."""
    ne, w = arr.dofs.shape
    nm = arr.modes.shape[1]
    return (np.zeros((ne, nm)), np.zeros((ne, nm, w)), np.zeros((ne, nm, w, w)), np.zeros((ne, nm, w, w, w)))


@njit(cache=True)
def allocate_equations(arr):
    """Zeroed element tensors D, Dx, Dxx, Dxxx and Phi (n_x,), J (n_x, n_x) for :func:`equations`."""
    n = arr.coord_row.shape[0]
    D, Dx, Dxx, Dxxx = allocate_tensors(arr)
    return D, Dx, Dxx, Dxxx, np.zeros(n), np.zeros((n, n))


@njit(cache=True)
def equations(arr, x, D, Dx, Dxx, Dxxx, Phi, J):
    """Element tensors, constraint equations Phi and their Jacobian J at x (n_x,), in place."""
    element_tensors(arr, x, D, Dx, Dxx, Dxxx)
    constraints(arr, x, D, Dx, Phi, J)


@njit(cache=True)
def constraints(arr, x, D, Dx, Phi, J):
    """Overwrite Phi (n_x,) and its Jacobian J (n_x, n_x) from element tensors D, Dx."""
    Phi[:] = 0.0
    J[:] = 0.0
    for i in range(x.shape[0]):
        row = arr.coord_row[i]
        if row >= 0:
            Phi[row] = x[i]
            J[row, i] = 1.0
    for e in range(arr.family.shape[0]):
        for k in range(arr.nmode[e]):
            row = arr.mode_row[arr.modes[e, k]]
            if row < 0:
                continue
            Phi[row] = D[e, k]
            for a in range(arr.ndof[e]):
                J[row, arr.dofs[e, a]] += Dx[e, k, a]


@njit(cache=True)
def contract2(arr, Dxx, u, w, out):
    """out (n_x,) = Phi_xx[u, w] for nodal vectors u, w (n_x,)."""
    out[:] = 0.0
    for e in range(arr.family.shape[0]):
        nd = arr.ndof[e]
        for k in range(arr.nmode[e]):
            row = arr.mode_row[arr.modes[e, k]]
            if row < 0:
                continue
            s = 0.0
            for a in range(nd):
                ua = u[arr.dofs[e, a]]
                if ua == 0.0:
                    continue
                for b in range(nd):
                    s += Dxx[e, k, a, b] * ua * w[arr.dofs[e, b]]
            out[row] = s


@njit(cache=True)
def along(arr, Dxxx, z, out):
    """out (ne, n_mode, n_dof, n_dof) = Dxxx . z, the element Hessians' derivative along the
    nodal vector z (n_x,), so that ``contract2(arr, out, u, w, .)`` = Phi_xxx[u, w, z]
    (rows of constrained modes only; the others are left zero)."""
    out[:] = 0.0
    ze = np.zeros(arr.dofs.shape[1])
    for e in range(arr.family.shape[0]):
        nd = arr.ndof[e]
        for c in range(nd):
            ze[c] = z[arr.dofs[e, c]]
        for k in range(arr.nmode[e]):
            if arr.mode_row[arr.modes[e, k]] >= 0:
                for a in range(nd):
                    for b in range(nd):
                        s = 0.0
                        for c in range(nd):
                            s += Dxxx[e, k, a, b, c] * ze[c]
                        out[e, k, a, b] = s


@njit(cache=True)
def newton(arr, x, b, tol, max_iter):
    """Solve Phi(x) = b in place from the guess x (n_x,). Returns (iterations, residual
    inf-norm, condition flag) with flag 0 = converged, 1 = no convergence,
    2 = singular Jacobian."""
    D, Dx, Dxx, Dxxx, Phi, J = allocate_equations(arr)
    res = np.inf
    for it in range(max_iter + 1):
        equations(arr, x, D, Dx, Dxx, Dxxx, Phi, J)
        res = np.max(np.abs(Phi - b))
        if res <= tol:
            return it, res, 0
        if it == max_iter:
            break
        if it == 0 and np.linalg.cond(J) > 1e13:
            return it, res, 2
        x -= np.linalg.solve(J, Phi - b)
    return max_iter, res, 1


@njit(cache=True)
def input_jacobian(arr, x):
    """F_q = J^-1 rhs_q at a solved configuration x; (n_x, n_q)."""
    D, Dx, Dxx, Dxxx, Phi, J = allocate_equations(arr)
    equations(arr, x, D, Dx, Dxx, Dxxx, Phi, J)
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


@njit(cache=True)
def rates(arr, x, qdot, qddot, v, a, Fd, Fdv, Fda):
    """The part of :func:`motion` that reduced_sample needs (no F_{q^d q^d}): overwrites
    v, a (n_x,), Fd, Fdv, Fda (n_x, n_d) by LU solves with the constraint Jacobian J
    (never its inverse). Returns the element tensors D, Dx, Dxx and J (n_x, n_x)."""
    n = x.shape[0]
    D, Dx, Dxx, Dxxx, Phi, J = allocate_equations(arr)
    equations(arr, x, D, Dx, Dxx, Dxxx, Phi, J)
    Fq = np.linalg.solve(J, arr.rhs_q)
    nr = arr.n_input
    nd = Fq.shape[1] - nr
    v[:] = Fq @ qdot
    tmp = np.empty(n)
    contract2(arr, Dxx, v, v, tmp)
    a[:] = Fq @ qddot - np.linalg.solve(J, tmp)
    FdT = np.ascontiguousarray(Fq[:, nr:].T)  # (nd, n): rows are the columns of F_q^d
    Fd[:] = FdT.T
    rhs_v = np.empty((n, nd))  # implicit differentiation, one column per dynamic coordinate
    col = np.empty(n)
    for i in range(nd):
        contract2(arr, Dxx, FdT[i], v, col)
        rhs_v[:, i] = col
    Fdv[:] = -np.linalg.solve(J, rhs_v)
    FdvT = np.ascontiguousarray(Fdv.T)
    rhs_a = np.empty((n, nd))
    tmp2 = np.empty(n)
    Dv = np.empty(Dxx.shape)
    along(arr, Dxxx, v, Dv)
    for i in range(nd):
        contract2(arr, Dv, FdT[i], v, col)
        contract2(arr, Dxx, FdT[i], a, tmp)
        contract2(arr, Dxx, FdvT[i], v, tmp2)
        rhs_a[:, i] = col + tmp + 2.0 * tmp2
    Fda[:] = -np.linalg.solve(J, rhs_a)
    return D, Dx, Dxx, J


@njit(cache=True)
def motion(arr, x, qdot, qddot, v, a, Fd, Fdv, Fdd, Fda):
    """Transfer-function derivatives at a solved configuration x for input rates qdot,
    qddot (n_q,) (all of q, dynamic included). Overwrites
    v = F_q qdot, a = F_q qddot + F_qq qdot qdot (n_x,), Fd = F_q^d (n_x, n_d),
    Fdv = F_{q^d q} qdot (n_x, n_d), Fdd = F_{q^d q^d} (n_x, n_d, n_d),
    Fda = F_{q^d q} qddot + F_{q^d q q} qdot qdot (n_x, n_d)."""
    n = x.shape[0]
    nd = Fd.shape[1]
    D, Dx, Dxx, J = rates(arr, x, qdot, qddot, v, a, Fd, Fdv, Fda)
    FdT = np.ascontiguousarray(Fd.T)
    rhs_dd = np.empty((n, nd * nd))
    col = np.empty(n)
    for i in range(nd):
        for j in range(i, nd):
            contract2(arr, Dxx, FdT[i], FdT[j], col)
            rhs_dd[:, i * nd + j] = col
            rhs_dd[:, j * nd + i] = col
    Fdd[:] = (-np.linalg.solve(J, rhs_dd)).reshape(n, nd, nd)
    return D, Dx, Dxx


@njit(cache=True)
def add_adjoint_curvature(arr, Dxx, mu, Fd, Kb):
    """Kb (n_d, n_d) += sum_k r_k F_{q^d q^d}[k] in adjoint form: with mu = J^-T r (the
    constraint forces), F_{q^d q^d} = -J^-1 Phi_xx[F_d, F_d] gives
    -sum_rows mu_row Phi_row,xx[F_d, F_d], contracted element by element on the rows of
    F_d at the element's coordinates (only deformation-mode rows have curvature)."""
    nd = Fd.shape[1]
    width = arr.dofs.shape[1]
    H = np.zeros((width, width))
    G = np.zeros((width, nd))
    for e in range(arr.family.shape[0]):
        ne = arr.ndof[e]
        H[:] = 0.0
        active = False
        for k in range(arr.nmode[e]):
            row = arr.mode_row[arr.modes[e, k]]
            if row < 0 or mu[row] == 0.0:
                continue
            active = True
            for p in range(ne):
                for q in range(ne):
                    H[p, q] -= mu[row] * Dxx[e, k, p, q]
        if not active:
            continue
        for p in range(ne):  # G = H F_d[dofs_e]
            for j in range(nd):
                s = 0.0
                for q in range(ne):
                    s += H[p, q] * Fd[arr.dofs[e, q], j]
                G[p, j] = s
        for i in range(nd):
            for p in range(ne):
                f = Fd[arr.dofs[e, p], i]
                if f == 0.0:
                    continue
                for j in range(nd):
                    Kb[i, j] += f * G[p, j]


@njit(cache=True)
def nodal_arrays(arr, x, v, a, D, Dx, Dxx, M, r, C, K):
    """Global nodal arrays at (x, v, a): overwrites M (n_x,n_x), r = M a - f (n_x,),
    C = -f_v, K = (M a - f)_x (n_x, n_x), from point masses, loads and all elements."""
    n = x.shape[0]
    M[:] = 0.0
    C[:] = 0.0
    K[:] = 0.0
    for i in range(n):
        M[i, i] = arr.nodal_mass[i]
        r[i] = arr.nodal_mass[i] * a[i] - arr.nodal_force[i]
    w = arr.dofs.shape[1]
    xe = np.zeros(w)
    ve = np.zeros(w)
    ae = np.zeros(w)
    Me = np.zeros((w, w))
    re = np.zeros(w)
    Ce = np.zeros((w, w))
    Ke = np.zeros((w, w))
    for e in range(arr.family.shape[0]):
        nd = arr.ndof[e]
        for i in range(nd):
            g = arr.dofs[e, i]
            xe[i] = x[g]
            ve[i] = v[g]
            ae[i] = a[g]
        Me[:] = 0.0
        re[:] = 0.0
        Ce[:] = 0.0
        Ke[:] = 0.0
        fam = arr.family[e]
        if fam == FAMILY_PLANAR_BEAM:
            planar_beam.inertia(xe, ve, ae, arr.ipar[e], arr.gravity, Me, re, Ce, Ke)
        elif fam == FAMILY_PLANAR_TRUSS:
            planar_truss.inertia(xe, ve, ae, arr.ipar[e], arr.gravity, Me, re, Ce, Ke)
        elif fam == FAMILY_SPATIAL_TRUSS:
            spatial_truss.inertia(xe, ve, ae, arr.ipar[e], arr.gravity, Me, re, Ce, Ke)
        elif fam == FAMILY_RIGID_BODY:
            rigid_body.inertia(xe, ve, ae, arr.ipar[e], arr.gravity, Me, re, Ce, Ke)
        elif fam == FAMILY_SPATIAL_BEAM:
            spatial_beam.inertia(xe, ve, ae, arr.ipar[e], arr.gravity, Me, re, Ce, Ke)
        add_elastic(arr.nmode[e], nd, D[e], Dx[e], Dxx[e], ve, arr.stiffness[e], arr.damping[e], arr.stress0[e],
                    re, Ce, Ke)
        for i in range(nd):
            gi = arr.dofs[e, i]
            r[gi] += re[i]
            for j in range(nd):
                gj = arr.dofs[e, j]
                M[gi, gj] += Me[i, j]
                C[gi, gj] += Ce[i, j]
                K[gi, gj] += Ke[i, j]


@njit(cache=True)
def reduced_sample(arr, x, qdot, qddot, Mb, Cb, Kb, fd, Fd, Fdv, Fda):
    """Reduced linearized equations at one configuration x and input rates
    (qdot, qddot) (n_q,): overwrites Mb, Cb, Kb (n_d, n_d) of eq. (5), (10) and
    fd (n_d,) = F_d^T (M a - f), the additional forces of eq. (7) (the residual of
    the reduced equations (4) when qdot, qddot include dynamic rates). Also writes the
    transfer-function derivatives Fd, Fdv, Fda (n_x, n_d) used by eq. (11)."""
    n = x.shape[0]
    v = np.empty(n)
    a = np.empty(n)
    D, Dx, Dxx, J = rates(arr, x, qdot, qddot, v, a, Fd, Fdv, Fda)
    M = np.empty((n, n))
    r = np.empty(n)
    C = np.empty((n, n))
    K = np.empty((n, n))
    nodal_arrays(arr, x, v, a, D, Dx, Dxx, M, r, C, K)
    MFd = M @ Fd
    CFd = C @ Fd
    Mb[:] = Fd.T @ MFd
    Cb[:] = Fd.T @ CFd + 2.0 * (MFd.T @ Fdv)
    Kb[:] = Fd.T @ (K @ Fd) + MFd.T @ Fda + Fd.T @ (C @ Fdv)
    add_adjoint_curvature(arr, Dxx, np.linalg.solve(J.T, r), Fd, Kb)
    fd[:] = Fd.T @ r


@njit(parallel=True, cache=True)
def linearize_samples(arr, X, qdots, qddots, Mb, Cb, Kb, fd, Fd, Fdv, Fda):
    """For every sample j (prange) and every rate set s: reduced_sample at X[j] with
    qdots[s], qddots[s] (S, n_q). Outputs Mb, Cb, Kb (S, p, n_d, n_d), fd (S, p, n_d),
    Fd, Fdv, Fda (S, p, n_x, n_d)."""
    p = X.shape[0]
    for j in prange(p):
        for s in range(qdots.shape[0]):
            reduced_sample(arr, X[j], qdots[s], qddots[s], Mb[s, j], Cb[s, j], Kb[s, j], fd[s, j],
                           Fd[s, j], Fdv[s, j], Fda[s, j])
