"""Shared layout of the flexible-multibody kernels (element families, padding).

Convention for every multibody kernel (``planar_*``, ``elastic``, ``outputs``,
``assembly``): ``@njit(cache=True)`` functions of float64 / int64 arrays and scalars
only; outputs go into caller-allocated arrays that the kernel adds to or overwrites as
its docstring says. Element kernels work on the element's local nodal coordinates
``xe`` (its row of ``dofs``); local tensors are as wide as the widest family present in
the compiled model (``dofs.shape[1]`` coordinates, ``modes.shape[1]`` modes), so a planar
model keeps planar widths and a spatial one gets its own; a kernel uses only its leading
entries. A family
is an integer id below, a deformation kernel and optionally an inertia kernel;
``assembly`` dispatches on the id, so adding a (spatial) family means a kernel module,
an id and one branch per dispatcher.
"""

FAMILY_PLANAR_BEAM = 0
FAMILY_PLANAR_TRUSS = 1
FAMILY_PLANAR_HINGE = 2
