"""Assembly of an element model's equations of motion: nodal inertia/elastic arrays summed
over the element families and the reduced linearized equations (eq. 5, 7, 9, 10 of
Schwab & Meijaard 2001) per sample, parallel over samples with ``prange``.

The constraint equations and element tensors live in :mod:`.constraints`, the transfer
function and its derivatives in :mod:`.transfer`; ``ModelArrays``, ``allocate_tensors``,
``element_tensors``, ``input_jacobian`` and ``track`` are also reachable through this module.
"""

import numpy as np
from numba import njit, prange

from .constraints import ModelArrays, allocate_tensors, element_tensors
from .elastic import add_elastic
from .layout import FAMILY_PLANAR_BEAM, FAMILY_PLANAR_TRUSS, FAMILY_RIGID_BODY, FAMILY_SPATIAL_BEAM, FAMILY_SPATIAL_TRUSS
from . import planar_beam, planar_truss, rigid_body, spatial_beam, spatial_truss
from .transfer import input_jacobian, rates, track

__all__ = ["nodal_arrays", "add_adjoint_curvature", "reduced_sample", "linearize_samples",
           "ModelArrays", "allocate_tensors", "element_tensors", "input_jacobian", "track"]

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
