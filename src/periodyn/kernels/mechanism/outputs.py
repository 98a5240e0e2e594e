"""Output functionals y(x) of the nodal coordinates, with gradients (for linear
output maps ``G = y_x F_q^d``)."""

import numpy as np
from numba import njit

from ..elements.jets import rotation_coefficients
from ..elements.rotation import rotation_matrix


@njit(cache=True)
def midpoint_deflection(xe, reference_length, grad):
    """Signed distance of point m from the line through a and b, divided by
    reference_length (m): ``((x_b - x_a) x (x_m - x_a)) / (|x_b - x_a| L)``.

    xe = [x_a, y_a, x_m, y_m, x_b, y_b] (m); overwrites grad (6,) with dy/dxe (1/m).
    Returns y (dimensionless)."""
    ux = xe[4] - xe[0]
    uy = xe[5] - xe[1]
    wx = xe[2] - xe[0]
    wy = xe[3] - xe[1]
    cross = ux * wy - uy * wx
    length = np.sqrt(ux * ux + uy * uy)
    scale = 1.0 / (length * reference_length)
    dux = wy * scale - cross * ux * scale / (length * length)
    duy = -wx * scale - cross * uy * scale / (length * length)
    dwx = -uy * scale
    dwy = ux * scale
    grad[0] = -dux - dwx
    grad[1] = -duy - dwy
    grad[2] = dwx
    grad[3] = dwy
    grad[4] = dux
    grad[5] = duy
    return cross * scale


@njit(cache=True)
def body_component(xe, direction, scale, grad):
    """Component along ``direction`` (3,) (body components of orientation node o) of the
    position of point m relative to point a, in o's frame, over scale (m):
    ``d . R(lam)^T (x_m - x_a) / scale``.

    xe = [x_a (3), lam (4), x_m (3)]; overwrites grad (10,) with dy/dxe. Returns y."""
    R = np.empty((3, 3))
    rotation_matrix(xe[3:7], R)
    Q = rotation_coefficients()
    u = xe[7:10] - xe[0:3]
    Rd = R @ direction
    grad[:] = 0.0
    for i in range(3):
        grad[i] = -Rd[i] / scale
        grad[7 + i] = Rd[i] / scale
        for k in range(3):
            w = direction[k] * u[i] / scale
            for j in range(4):
                for m in range(4):
                    grad[3 + j] += 2.0 * Q[i, k, j, m] * xe[3 + m] * w
    return (Rd @ u) / scale
