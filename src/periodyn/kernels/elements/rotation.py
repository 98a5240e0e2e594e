"""Euler parameters (unit quaternions, scalar first) ``lam = (l0, l1, l2, l3) =
(cos(phi/2), sin(phi/2) n)`` for a rotation phi (rad) about the unit axis n.

``R(lam) = (l0^2 - e.e) I + 2 e e^T + 2 l0 [e]x`` (e = (l1, l2, l3)) maps body to global
components; it is quadratic in lam and orthogonal when lam . lam = 1.
``G(lam)`` (3, 4) gives the angular velocity in body components ``Omega = 2 G(lam) lam'``;
G is linear in lam, ``G(lam) lam = 0`` and ``G(a) b = -G(b) a``.
The quaternion product ``a * b`` composes rotations: ``R(a * b) = R(a) R(b)``.
"""

from numba import njit


@njit(cache=True)
def rotation_matrix(lam, R):
    """Overwrite R (3,3) with R(lam) for lam (4,)."""
    l0 = lam[0]
    ee = lam[1] * lam[1] + lam[2] * lam[2] + lam[3] * lam[3]
    for i in range(3):
        for j in range(3):
            R[i, j] = 2.0 * lam[1 + i] * lam[1 + j]
        R[i, i] += l0 * l0 - ee
    R[0, 1] -= 2.0 * l0 * lam[3]
    R[1, 0] += 2.0 * l0 * lam[3]
    R[0, 2] += 2.0 * l0 * lam[2]
    R[2, 0] -= 2.0 * l0 * lam[2]
    R[1, 2] -= 2.0 * l0 * lam[1]
    R[2, 1] += 2.0 * l0 * lam[1]


@njit(cache=True)
def g_matrix(lam, G):
    """Overwrite G (3,4) with G(lam): rows (-l1, l0, l3, -l2), (-l2, -l3, l0, l1),
    (-l3, l2, -l1, l0)."""
    l0, l1, l2, l3 = lam[0], lam[1], lam[2], lam[3]
    G[0, 0], G[0, 1], G[0, 2], G[0, 3] = -l1, l0, l3, -l2
    G[1, 0], G[1, 1], G[1, 2], G[1, 3] = -l2, -l3, l0, l1
    G[2, 0], G[2, 1], G[2, 2], G[2, 3] = -l3, l2, -l1, l0


@njit(cache=True)
def product(a, b, out):
    """Overwrite out (4,) with the quaternion product a * b (out may not be a or b)."""
    out[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3]
    out[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2]
    out[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1]
    out[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]

