"""Numba-jitted kernels: the only compiled code in periodyn.

Convention: ``@njit(cache=True)``; float64/complex128 arrays and int loop bounds only, no
Python objects; outputs are caller-allocated ``out`` arrays where a kernel fills a block.
One module per family: ``elements/`` (one module per element family and the geometry they
share), ``mechanism/`` (constraints, transfer function, assembly, the omega split),
``solvers/`` (banded, Floquet, Magnus, harmonic, implicit, ODE flows). Every kernel has a
plain-NumPy twin in the tests.

Compile cost (a first run after an install compiles every kernel it calls; profile one with
``benchmarks/compile_profile.py``): Numba links each kernel's callees into its own module and
has LLVM optimize the whole of it again (at -O1, :mod:`.optimization`), so a kernel costs
about the size of everything it calls, once per signature. Hence loops are serial (no
``parallel=True``: a sweep runs one thread per worker process, and a prange kernel
compiles its body again as a parallel region), a kernel is called with one signature
(float64 C-contiguous arrays, int64 scalars), and no thin jitted wrapper is put around a
large kernel.

Adding an element family (``tests/unit/kernels/test_element_families.py`` checks steps 1-5):

1. ``elements/<family>.py``: ``deformation(xe, par, D, Dx, Dxx, Dxxx)`` and, if the
   element has inertia, ``inertia(xe, ve, ae, ipar, gravity, Me, re, Ce, Ke)``, under the
   conventions of :mod:`.elements.layout` (which also documents the argument shapes).
2. ``elements/layout.py``: a new id ``FAMILY_<NAME>``.
3. ``mechanism/constraint_system.py``: one branch of ``planar_deformation`` or
   ``spatial_deformation`` (the modes; a planar family's id also joins ``PLANAR_FAMILIES``)
   and, with inertia, ``mechanism/assembly.py``: one branch of ``planar_inertia`` or
   ``spatial_inertia``. A model's packed arrays are of the class of its family set
   (``PlanarArrays``, ``SpatialArrays`` or, mixed, ``ModelArrays``) and each kernel compiles
   only that set's branches.
4. ``periodyn/model/``: the element's data class with ``family = FAMILY_<NAME>`` and its
   parameter rows (``par``, ``ipar``, nodes, modes), re-exported by ``periodyn.model``.
5. ``tests/twins/``: a plain-NumPy twin of each kernel, and a test in ``tests/unit/kernels/``
   that calls ``<family>.deformation`` (and ``<family>.inertia``) against it (~1e-13) and
   against finite differences of every derivative order.
"""

from . import optimization  # noqa: F401  (the kernels' level is set before any of them compiles)
