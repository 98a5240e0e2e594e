"""Shared layout of the flexible-multibody kernels (element families, array widths).

Convention for every multibody kernel (``planar_*``, ``spatial_*``, ``rotation``,
``elastic``, ``outputs``, ``assembly``): ``@njit(cache=True)`` functions of float64 /
int64 arrays and scalars only; outputs go into caller-allocated arrays that the kernel
adds to or overwrites as its docstring says. Element kernels work on the element's
local nodal coordinates ``xe`` (its row of ``dofs``); local tensors are as wide as the
widest family present in the compiled model (``dofs.shape[1]`` coordinates,
``modes.shape[1]`` modes), so a planar model keeps planar widths and a spatial one gets
its own; a kernel uses only its leading entries.

A family is an integer id below and a kernel module with

- ``deformation(xe, par, D, Dx, Dxx, Dxxx)``: overwrite the leading entries of D (nm,),
  Dx (nm, nx), Dxx (nm, nx, nx), Dxxx (nm, nx, nx, nx) with the deformation modes and
  their derivatives w.r.t. xe (nx,); par is the family's geometric parameter row;
- optionally ``inertia(xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)``: the element's
  inertia and distributed gravity at local coordinates, velocities and accelerations
  xe, ve, ae (nx,). ipar is the element's 1-D float inertia-parameter array whose
  layout the family module documents (the model's ``ipar`` array is zero-padded to the
  widest family), gravity (dim,) m/s^2. The kernel ADDS
  ``Me += M`` (nx, nx), ``re += M ae + convective terms - f_gravity`` (nx,),
  ``Ce += d re / d ve`` and ``Ke += d re / d xe`` (at fixed ve, ae) (nx, nx).

``assembly`` dispatches on the id, so adding a family means a kernel module, an id and
one branch per dispatcher.
"""

FAMILY_PLANAR_BEAM = 0
FAMILY_PLANAR_TRUSS = 1
FAMILY_PLANAR_HINGE = 2
FAMILY_SPATIAL_BEAM = 3
FAMILY_EULER_NORMALIZATION = 4
FAMILY_SPATIAL_TRUSS = 5
FAMILY_SPATIAL_HINGE = 6
FAMILY_RIGID_BODY = 7
FAMILY_RIGID_LINK = 8
