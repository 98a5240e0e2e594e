"""Element-family kernels: deformation modes and their derivatives per family (planar
truss, beam, hinge; spatial truss, beam, joints; rigid bodies), and the geometry they share
(rotations, jets, vector inertia, elastic laws, the array layout)."""
