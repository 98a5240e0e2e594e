"""Shared layout of the flexible-multibody kernels (element families, padding).

Convention for every multibody kernel (``planar_*``, ``elastic``, ``outputs``,
``assembly``): ``@njit(cache=True)`` functions of float64 / int64 arrays and scalars
only; outputs go into caller-allocated arrays that the kernel adds to or overwrites as
its docstring says. Element kernels work on the element's local nodal coordinates
``xe`` (its row of ``dofs``); local tensors are padded to ``MAX_DOF`` coordinates and
``MAX_MODE`` deformation modes so that all families share one array layout. A family
is an integer id below, a deformation kernel and optionally an inertia kernel;
``assembly`` dispatches on the id, so adding a (spatial) family means a kernel module,
an id and one branch per dispatcher.
"""

MAX_DOF = 6
MAX_MODE = 3
MAX_INTERP = 4

FAMILY_PLANAR_BEAM = 0
FAMILY_PLANAR_TRUSS = 1
FAMILY_PLANAR_HINGE = 2
FAMILY_SPATIAL_BEAM = 3
