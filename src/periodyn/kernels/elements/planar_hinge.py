"""Planar hinge element: relative rotation of two orientation coordinates;
local coordinates ``xe = [phi_p, phi_q]`` (rad).

Deformation mode (rad): ``e1 = phi_q - phi_p - c`` with c the reference relative
rotation. Not wrapped to (-pi, pi]: a hinge may turn many times. par = [c].
The hinge has no inertia of its own.
"""

from numba import njit


@njit(cache=True)
def deformation(xe, par, D, Dx, Dxx, Dxxx):
    """Overwrite D[0] and its (constant) derivatives w.r.t. xe (2,)."""
    D[0] = xe[1] - xe[0] - par[0]
    Dx[0, 0] = -1.0
    Dx[0, 1] = 1.0
    Dxx[0, :2, :2] = 0.0
    Dxxx[0, :2, :2, :2] = 0.0
