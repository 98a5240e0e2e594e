"""Planar truss element: nodes p, q with positions; local coordinates
``xe = [x_p, y_p, x_q, y_q]`` (m).

Deformation mode (m): elongation ``e1 = l - l0``. par = [l0].
Inertia: consistent mass of a uniform bar, position linearly interpolated,
``r(s) = (1-s) x_p + s x_q``; mass[i, j] = rhoA l0 int N_i N_j ds, weights[i] = rhoA l0 int N_i ds.
Inertia parameters ``ipar`` (IPAR_SIZE = 6): ``[mass (2x2 row-major, kg), weights (2, kg)]``.
"""

IPAR_SIZE = 6

from numba import njit

from .planar_geometry import chord


@njit(cache=True)
def deformation(xe, par, D, Dx, Dxx, Dxxx):
    """Overwrite D[0], Dx[0,:4], Dxx[0,:4,:4], Dxxx[0,:4,:4,:4] with the elongation and
    its derivatives w.r.t. xe (4,)."""
    n = 4
    length, _, L1, L2, L3, _, _, _ = chord(xe, 0, 2, n)
    D[0] = length - par[0]
    Dx[0, :n] = L1
    Dxx[0, :n, :n] = L2
    Dxxx[0, :n, :n, :n] = L3


@njit(cache=True)
def inertia(xe, ve, ae, ipar, gravity, M, r, C, K):
    """Add the bar's mass matrix to M (2 dim, 2 dim) and ``M a - f_gravity`` to r (2 dim,)
    in dim = gravity.shape[0] dimensions (the spatial truss uses it too); the
    interpolation is linear in xe so C and K get nothing. ipar (>= 6,) as in the
    module docstring, gravity (dim,) m/s^2."""
    dim = gravity.shape[0]
    for i in range(2):
        for j in range(2):
            mij = ipar[2 * i + j]
            for c in range(dim):
                M[dim * i + c, dim * j + c] += mij
                r[dim * i + c] += mij * ae[dim * j + c]
        for c in range(dim):
            r[dim * i + c] -= ipar[4 + i] * gravity[c]
