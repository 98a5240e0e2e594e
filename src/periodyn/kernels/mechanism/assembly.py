"""Assembly of an element model's equations of motion: nodal inertia/elastic arrays summed
over the element families and the reduced linearized equations (eq. 5, 7, 9, 10 of
Schwab & Meijaard 2001) per sample.

The constraint equations and element tensors live in :mod:`.constraints`, the transfer
function and its derivatives in :mod:`.transfer`; ``ModelArrays``, ``allocate_tensors``,
``element_tensors``, ``input_jacobian`` and ``track`` are also reachable through this module.
"""

import numpy as np
from numba import njit
from numba.extending import overload

from .constraint_system import ModelArrays, PlanarArrays, SpatialArrays, allocate_tensors, element_tensors
from ..elements.elastic import add_elastic
from ..elements.layout import FAMILY_PLANAR_BEAM, FAMILY_PLANAR_TRUSS, FAMILY_RIGID_BODY, FAMILY_SPATIAL_BEAM, FAMILY_SPATIAL_TRUSS
from ..elements import planar_beam, planar_truss, rigid_body, spatial_beam, spatial_truss
from .lu import lu_solve_transposed
from .transfer import input_jacobian, rates, track

__all__ = ["element_arrays", "allocate_element_arrays", "nodal_arrays", "nodal_product", "add_adjoint_curvature", "reduced_sample",
           "ModelArrays", "allocate_tensors", "element_tensors", "input_jacobian", "track"]

@njit(cache=True)
def add_adjoint_curvature(arr, Dxx, mu, Ke):
    """Ke (ne, w, w) -= sum_k mu_row(k) Dxx[e, k] over each element's constrained modes:
    the term sum_k r_k F_{q^d q^d}[k] of the reduced stiffness in adjoint form. With
    mu = J^-T r (the constraint forces), F_{q^d q^d} = -J^-1 Phi_xx[F_d, F_d] gives
    F_d^T (-sum_rows mu_row Phi_row,xx) F_d, so the curvature joins the element stiffness
    blocks before they act on F_d (only deformation-mode rows have curvature)."""
    for e in range(arr.family.shape[0]):
        ne = arr.ndof[e]
        for k in range(arr.nmode[e]):
            row = arr.mode_row[arr.modes[e, k]]
            if row < 0 or mu[row] == 0.0:
                continue
            m = mu[row]
            for p in range(ne):
                for q in range(ne):
                    Ke[e, p, q] -= m * Dxx[e, k, p, q]


def inertia(arr, family, xe, ve, ae, ipar, gravity, Me, re, Ce, Ke):
    """The inertia kernel of the element family with id ``family`` (a family without inertia
    does nothing), dispatched over the families of ``arr``'s class (see
    :mod:`.constraint_system`; in jitted code the dispatch is chosen at typing time)."""
    _INERTIA[type(arr)](family, xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)


@njit(cache=True, inline="always")
def planar_inertia(family, xe, ve, ae, ipar, gravity, Me, re, Ce, Ke):
    """:func:`inertia` over the planar families (other ids do nothing)."""
    if family == FAMILY_PLANAR_BEAM:
        planar_beam.inertia(xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)
    elif family == FAMILY_PLANAR_TRUSS:
        planar_truss.inertia(xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)


@njit(cache=True, inline="always")
def spatial_inertia(family, xe, ve, ae, ipar, gravity, Me, re, Ce, Ke):
    """:func:`inertia` over the spatial families (other ids do nothing)."""
    if family == FAMILY_SPATIAL_TRUSS:
        spatial_truss.inertia(xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)
    elif family == FAMILY_RIGID_BODY:
        rigid_body.inertia(xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)
    elif family == FAMILY_SPATIAL_BEAM:
        spatial_beam.inertia(xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)


@njit(cache=True, inline="always")
def mixed_inertia(family, xe, ve, ae, ipar, gravity, Me, re, Ce, Ke):
    """:func:`inertia` over every family."""
    planar_inertia(family, xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)
    spatial_inertia(family, xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)


_INERTIA = {PlanarArrays: planar_inertia, SpatialArrays: spatial_inertia, ModelArrays: mixed_inertia}


@overload(inertia, inline="always")
def _inertia_of_class(arr, family, xe, ve, ae, ipar, gravity, Me, re, Ce, Ke):
    kernel = _INERTIA[arr.instance_class]

    def impl(arr, family, xe, ve, ae, ipar, gravity, Me, re, Ce, Ke):
        kernel(family, xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)
    return impl


@njit(cache=True)
def element_arrays(arr, x, v, a, D, Dx, Dxx, Me, Ce, Ke, r):
    """Element inertia/elastic arrays at (x, v, a): overwrites Me, Ce, Ke (ne, w, w) (the
    element's mass matrix, -d f / d ve and d (M a - f) / d xe on its leading ndof
    coordinates) and r = M a - f (n_x,) summed over point masses, loads and elements."""
    for i in range(x.shape[0]):
        r[i] = arr.nodal_mass[i] * a[i] - arr.nodal_force[i]
    w = arr.dofs.shape[1]
    xe = np.zeros(w)
    ve = np.zeros(w)
    ae = np.zeros(w)
    re = np.zeros(w)
    Me[:] = 0.0
    Ce[:] = 0.0
    Ke[:] = 0.0
    for e in range(arr.family.shape[0]):
        nd = arr.ndof[e]
        for i in range(nd):
            g = arr.dofs[e, i]
            xe[i] = x[g]
            ve[i] = v[g]
            ae[i] = a[g]
        re[:] = 0.0
        inertia(arr, arr.family[e], xe, ve, ae, arr.ipar[e], arr.gravity, Me[e], re, Ce[e], Ke[e])
        add_elastic(arr.nmode[e], nd, D[e], Dx[e], Dxx[e], ve, arr.stiffness[e], arr.damping[e], arr.stress0[e],
                    re, Ce[e], Ke[e])
        for i in range(nd):
            r[arr.dofs[e, i]] += re[i]


@njit(cache=True)
def allocate_element_arrays(arr):
    """Me, Ce, Ke (ne, w, w) for :func:`element_arrays`."""
    ne, w = arr.dofs.shape
    return np.empty((ne, w, w)), np.empty((ne, w, w)), np.empty((ne, w, w))


@njit(cache=True)
def nodal_arrays(arr, x, v, a, D, Dx, Dxx, M, r, C, K):
    """Global nodal arrays at (x, v, a): overwrites M (n_x,n_x), r = M a - f (n_x,),
    C = -f_v, K = (M a - f)_x (n_x, n_x), from point masses, loads and all elements."""
    Me, Ce, Ke = allocate_element_arrays(arr)
    element_arrays(arr, x, v, a, D, Dx, Dxx, Me, Ce, Ke, r)
    M[:] = 0.0
    C[:] = 0.0
    K[:] = 0.0
    for i in range(x.shape[0]):
        M[i, i] = arr.nodal_mass[i]
    for e in range(arr.family.shape[0]):
        nd = arr.ndof[e]
        for i in range(nd):
            gi = arr.dofs[e, i]
            for j in range(nd):
                gj = arr.dofs[e, j]
                M[gi, gj] += Me[e, i, j]
                C[gi, gj] += Ce[e, i, j]
                K[gi, gj] += Ke[e, i, j]


@njit(cache=True)
def nodal_product(arr, diag, Ee, X, out):
    """out (n_x, k) = A X for X (n_x, k), with the nodal matrix A = diag(diag) + the
    element blocks Ee (ne, w, w) scattered to their coordinates, never formed (its cost
    grows with the elements, not with n_x^2)."""
    k = X.shape[1]
    for i in range(X.shape[0]):
        for c in range(k):
            out[i, c] = diag[i] * X[i, c]
    for e in range(arr.family.shape[0]):
        nd = arr.ndof[e]
        for i in range(nd):
            gi = arr.dofs[e, i]
            for j in range(nd):
                m = Ee[e, i, j]
                if m == 0.0:
                    continue
                gj = arr.dofs[e, j]
                for c in range(k):
                    out[gi, c] += m * X[gj, c]


@njit(cache=True)
def reduced_sample(arr, x, qdot, qddot, load, Mb, Cb, Kb, fd, Fd, Fdv, Fda):
    """Reduced linearized equations at one configuration x and input rates
    (qdot, qddot) (n_q,), with nodal loads ``load`` (n_x,) besides the constant ones:
    overwrites Mb, Cb, Kb (n_d, n_d) of eq. (5), (10) and
    fd (n_d,) = F_d^T (M a - f), the additional forces of eq. (7) (the residual of
    the reduced equations (4) when qdot, qddot include dynamic rates). Also writes the
    transfer-function derivatives Fd, Fdv, Fda (n_x, n_d) used by eq. (11). The nodal
    M, C, K (with the constraint curvature, :func:`add_adjoint_curvature`) act through
    their element blocks (:func:`nodal_product`)."""
    n = x.shape[0]
    nd = Fd.shape[1]
    v = np.empty(n)
    a = np.empty(n)
    D, Dx, Dxx, LU, piv = rates(arr, x, qdot, qddot, v, a, Fd, Fdv, Fda)
    Me, Ce, Ke = allocate_element_arrays(arr)
    r = np.empty(n)
    element_arrays(arr, x, v, a, D, Dx, Dxx, Me, Ce, Ke, r)
    r -= load
    add_adjoint_curvature(arr, Dxx, lu_solve_transposed(LU, piv, r), Ke)
    zero = np.zeros(n)
    MFd = np.empty((n, nd))
    CFd = np.empty((n, nd))
    KFd = np.empty((n, nd))
    CFdv = np.empty((n, nd))
    nodal_product(arr, arr.nodal_mass, Me, Fd, MFd)
    nodal_product(arr, zero, Ce, Fd, CFd)
    nodal_product(arr, zero, Ke, Fd, KFd)
    nodal_product(arr, zero, Ce, Fdv, CFdv)
    Mb[:] = Fd.T @ MFd
    Cb[:] = Fd.T @ CFd + 2.0 * (MFd.T @ Fdv)
    Kb[:] = Fd.T @ (KFd + CFdv) + MFd.T @ Fda
    fd[:] = Fd.T @ r
