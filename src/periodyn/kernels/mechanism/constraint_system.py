"""Constraint equations of an element model, summed over its element families
(Schwab & Meijaard 2001, eq. 1-2): ``Phi(x) = b(q) = rhs0 + rhs_q q`` with one row per
fixed, prescribed or dynamic nodal coordinate (``Phi = x_i``) and per rigid, prescribed or
flexible deformation mode (``Phi = D_k(x)``); ``q = [q^r, q^d]``. Also the model's packed
arrays (:data:`ModelArrays`), the element tensors and their contractions.

Nothing here assumes two dimensions: a family is dispatched by its integer id to its
deformation kernel, and local arrays are as wide as the widest family of the model (the
widths of ``dofs`` and ``modes``, see :mod:`.layout`).

Dispatch per family set: the packed arrays come in three namedtuple classes with the same
fields, :data:`PlanarArrays` (planar families only), :data:`SpatialArrays` (spatial only)
and :data:`ModelArrays` (any mix), chosen by :func:`arrays_class`. The family dispatch
(:func:`deformation`) is chosen at typing time from the arrays' class, so every kernel
taking ``arr`` is compiled once per class in use and a planar model never compiles (nor
links and optimizes again) the spatial families, nor a spatial model the planar ones.

The dispatch is inlined into its caller (``inline="always"``, as are small helpers on the
way from the entry points to the family kernels): a function Numba compiles on its own
links, optimizes and generates machine code for all its callees once more, so each level
less between the entry points and the families shortens a cold compile (by a few seconds
per level for the spatial families).
"""

from collections import namedtuple

import numpy as np
from numba import njit
from numba.extending import overload

from ..elements.layout import (FAMILY_EULER_NORMALIZATION, FAMILY_PLANAR_BEAM, FAMILY_PLANAR_HINGE, FAMILY_PLANAR_TRUSS,
                     FAMILY_RIGID_LINK, FAMILY_SPATIAL_BEAM, FAMILY_SPATIAL_HINGE, FAMILY_SPATIAL_TRUSS)
from ..elements import planar_beam, planar_hinge, planar_truss, spatial_beam, spatial_joints, spatial_truss

TWO_PI = 2.0 * np.pi

_FIELDS = [
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
]
ModelArrays = namedtuple("ModelArrays", _FIELDS)  # any mix of element families
PlanarArrays = namedtuple("PlanarArrays", _FIELDS)  # planar families only
SpatialArrays = namedtuple("SpatialArrays", _FIELDS)  # spatial families only
PLANAR_FAMILIES = frozenset((FAMILY_PLANAR_BEAM, FAMILY_PLANAR_TRUSS, FAMILY_PLANAR_HINGE))


def arrays_class(families) -> type:
    """The packed-arrays class for a model with element family ids ``families``: planar
    (also a model without elements: the smaller dispatch), spatial, or for a mix ModelArrays."""
    planar = {int(f) in PLANAR_FAMILIES for f in families}
    if planar <= {True}:
        return PlanarArrays
    return SpatialArrays if planar == {False} else ModelArrays


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
        deformation(arr, arr.family[e], xe, arr.par[e], D[e], Dx[e], Dxx[e], Dxxx[e])


def deformation(arr, family, xe, par, D, Dx, Dxx, Dxxx):
    """The deformation kernel of the element family with id ``family``, dispatched over the
    families of ``arr``'s class (a family without modes, such as a rigid body, leaves D and
    its derivatives as they are). In jitted code the dispatch is chosen at typing time."""
    _DEFORMATION[type(arr)](family, xe, par, D, Dx, Dxx, Dxxx)


@njit(cache=True, inline="always")
def planar_deformation(family, xe, par, D, Dx, Dxx, Dxxx):
    """:func:`deformation` over the planar families (other ids do nothing)."""
    if family == FAMILY_PLANAR_BEAM:
        planar_beam.deformation(xe, par, D, Dx, Dxx, Dxxx)
    elif family == FAMILY_PLANAR_TRUSS:
        planar_truss.deformation(xe, par, D, Dx, Dxx, Dxxx)
    elif family == FAMILY_PLANAR_HINGE:
        planar_hinge.deformation(xe, par, D, Dx, Dxx, Dxxx)


@njit(cache=True, inline="always")
def spatial_deformation(family, xe, par, D, Dx, Dxx, Dxxx):
    """:func:`deformation` over the spatial families (other ids do nothing)."""
    if family == FAMILY_SPATIAL_BEAM:
        spatial_beam.deformation(xe, par, D, Dx, Dxx, Dxxx)
    elif family == FAMILY_EULER_NORMALIZATION:
        spatial_joints.normalization(xe, par, D, Dx, Dxx, Dxxx)
    elif family == FAMILY_SPATIAL_TRUSS:
        spatial_truss.deformation(xe, par, D, Dx, Dxx, Dxxx)
    elif family == FAMILY_SPATIAL_HINGE:
        spatial_joints.hinge(xe, par, D, Dx, Dxx, Dxxx)
    elif family == FAMILY_RIGID_LINK:
        spatial_joints.rigid_link(xe, par, D, Dx, Dxx, Dxxx)


@njit(cache=True, inline="always")
def mixed_deformation(family, xe, par, D, Dx, Dxx, Dxxx):
    """:func:`deformation` over every family (one of the two sets matches)."""
    planar_deformation(family, xe, par, D, Dx, Dxx, Dxxx)
    spatial_deformation(family, xe, par, D, Dx, Dxx, Dxxx)


_DEFORMATION = {PlanarArrays: planar_deformation, SpatialArrays: spatial_deformation, ModelArrays: mixed_deformation}


@overload(deformation, inline="always")
def _deformation_of_class(arr, family, xe, par, D, Dx, Dxx, Dxxx):
    kernel = _DEFORMATION[arr.instance_class]

    def impl(arr, family, xe, par, D, Dx, Dxx, Dxxx):
        kernel(family, xe, par, D, Dx, Dxx, Dxxx)
    return impl


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
def equations(arr, x, b, D, Dx, Dxx, Dxxx, Phi, J):
    """Element tensors, constraint equations Phi and their Jacobian J at x (n_x,), in place,
    for the right-hand side b (n_x,) (see :func:`constraints`; pass ``arr.rhs0`` where only
    the tensors and J are wanted)."""
    element_tensors(arr, x, D, Dx, Dxx, Dxxx)
    constraints(arr, x, b, D, Dx, Phi, J)


@njit(cache=True)
def constraints(arr, x, b, D, Dx, Phi, J):
    """Overwrite Phi (n_x,) and its Jacobian J (n_x, n_x) from element tensors D, Dx.

    The rotation of a spatial hinge is an angle, defined modulo 2 pi (its mode is continuous
    only within one turn of the reference, :mod:`.spatial_joints`): its row is taken on the
    branch nearest its right-hand side b (n_x,), so that ``Phi - b`` is continuous however
    many turns a prescribed hinge makes."""
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
            if k == spatial_joints.HINGE_ROTATION and arr.family[e] == FAMILY_SPATIAL_HINGE:
                Phi[row] += TWO_PI * np.round((b[row] - Phi[row]) / TWO_PI)
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
