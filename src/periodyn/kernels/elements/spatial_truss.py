"""Spatial truss element: nodes p, q with positions; local coordinates
``xe = [x_p, y_p, z_p, x_q, y_q, z_q]`` (m). Deformation mode (m): elongation
``e1 = |x_q - x_p| - l0``, par = [l0]; derivatives by the Taylor jets of :mod:`.jets`.
Inertia: the bar of :mod:`.planar_truss` (its kernel works in any dimension), ipar =
[mass (2x2 row-major, kg), weights (2, kg)].
"""

import numpy as np
from numba import njit

from . import jets
from .planar_truss import inertia
from .spatial_joints import store

__all__ = ["deformation", "inertia"]


@njit(cache=True)
def deformation(xe, par, D, Dx, Dxx, Dxxx):
    """Overwrite mode 0 with the elongation and its derivatives w.r.t. xe (6,)."""
    n = 6
    m = jets.size(n)
    u = np.empty((3, m))
    a = np.empty(m)
    for c in range(3):
        jets.seed(xe[3 + c], 3 + c, u[c])
        jets.seed(xe[c], c, a)
        jets.sub(u[c], a, u[c])
    jets.dot3(u, u, a)
    jets.sqrt(a, a)
    a[0] -= par[0]
    store(a, 0, n, D, Dx, Dxx, Dxxx)
