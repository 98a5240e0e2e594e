"""The reduced linearized equations of an element model as polynomials in the input speed
s (Schwab & Meijaard 2001, eq. 5, 7, 9, 10 with inputs that are functions of the driving
angle, q^r = g(theta), theta = s t, so q^r' = s g' and q^r'' = s^2 g''):
``C = C0 + s C1``, ``K = K0 + s K1 + s^2 K2``, ``f^d = f0 + s f1 + s^2 f2``, per sample.
Loads that are functions of theta enter r0.

At unit speed (rates g', g''), v, a, F_{q^d q} q' and F_{q^d q} q'' + F_{q^d q q} q' q'
scale with s, s^2, s, s^2 exactly, so the constraint Jacobian is factored and the transfer
function differentiated once per sample. Only the element arrays (cheap, one block per
element) are evaluated at s = -S, 0, +S and split into powers; the reduced matrices
then come from one product for all powers,
``F_d^T [M F_d, C0 F_d, C1 F_d + 2 M^T F_dv, K0 F_d, K1 F_d + C0 F_dv, K2 F_d + C1 F_dv + M^T F_da, r0, r1, r2]``,
formed as ``E_d^T J^-T [...]`` (F_d = J^-1 E_d, E_d = the dynamic columns of b_q) by
transposed solves with the sparse LU factors of J: ``nnz(L + U)`` per column, not the
``n_x n_d`` of a dense product, so a sample costs about n_d^2 times a few elements.
"""

import numpy as np
from numba import njit

from .assembly import add_adjoint_curvature, allocate_element_arrays, element_arrays, nodal_product
from .lu import lu_solve_transposed, lu_solve_transposed_many
from .transfer import rates


@njit(cache=True, inline="always")
def _element_powers(arr, x, v1, a1, load, D, Dx, Dxx, LU, piv, speed, Me, Ce, Ke, r):
    """Element arrays with the constraint curvature at input speed s, split into powers of s
    from s = -speed, 0, +speed: Me (ne, w, w); Ce (2, ne, w, w); Ke (3, ne, w, w); r (3, n_x).
    ``load`` (n_x,): nodal loads of this sample besides the model's constant ones."""
    n = x.shape[0]
    Cs = np.empty((3,) + Me.shape)
    Ks = np.empty((3,) + Me.shape)
    rs = np.empty((3, n))
    for i in range(3):
        s = (i - 1) * speed
        element_arrays(arr, x, s * v1, s * s * a1, D, Dx, Dxx, Me, Cs[i], Ks[i], rs[i])
        rs[i] -= load
        add_adjoint_curvature(arr, Dxx, lu_solve_transposed(LU, piv, rs[i]), Ks[i])
    Ce[0] = Cs[1]
    Ce[1] = 0.5 * (Cs[2] - Cs[0]) / speed
    Ke[0] = Ks[1]
    Ke[1] = 0.5 * (Ks[2] - Ks[0]) / speed
    Ke[2] = (0.5 * (Ks[2] + Ks[0]) - Ks[1]) / (speed * speed)
    r[0] = rs[1]
    r[1] = 0.5 * (rs[2] - rs[0]) / speed
    r[2] = (0.5 * (rs[2] + rs[0]) - rs[1]) / (speed * speed)


@njit(cache=True)
def split_sample(arr, x, qdot1, qddot1, load, speed, Mb, Cb, Kb, fd, Fd, Fdv, Fda):
    """At configuration x, for input rates ``s * qdot1`` and accelerations ``s^2 * qddot1``
    (n_q,) and nodal loads ``load`` (n_x,) besides the constant ones:
    overwrites Mb (n_d, n_d), Cb (2, n_d, n_d), Kb (3, n_d, n_d), fd (3, n_d) (powers of s of
    the reduced M, C, K and of f^d = F_d^T (M a - f)) and F_q^d, F_{q^d q} qdot1 and
    F_{q^d q} qddot1 + F_{q^d q q} qdot1 qdot1 (n_x, n_d); ``speed`` (rad/s) is where the element arrays are
    sampled (pick it so that the s^2 terms match the s^0 terms)."""
    n = x.shape[0]
    nd = Fd.shape[1]
    v1 = np.empty(n)
    a1 = np.empty(n)
    D, Dx, Dxx, LU, piv = rates(arr, x, qdot1, qddot1, v1, a1, Fd, Fdv, Fda)
    Me, _, _ = allocate_element_arrays(arr)
    Ce = np.empty((2,) + Me.shape)
    Ke = np.empty((3,) + Me.shape)
    r = np.empty((3, n))
    _element_powers(arr, x, v1, a1, load, D, Dx, Dxx, LU, piv, speed, Me, Ce, Ke, r)
    Z = np.empty((n, 6 * nd + 3))  # the right factors of F_d^T, block by block
    tmp = np.empty((n, nd))
    zero = np.zeros(n)
    MeT = np.ascontiguousarray(Me.transpose(0, 2, 1))
    # (diagonal, element blocks, factor, block of Z, weight): M^T terms from (M F_d)^T F_dv, (M F_d)^T F_da
    blocks = ((arr.nodal_mass, Me, Fd, 0, 1.0), (zero, Ce[0], Fd, 1, 1.0), (zero, Ce[1], Fd, 2, 1.0),
              (arr.nodal_mass, MeT, Fdv, 2, 2.0), (zero, Ke[0], Fd, 3, 1.0), (zero, Ke[1], Fd, 4, 1.0),
              (zero, Ce[0], Fdv, 4, 1.0), (zero, Ke[2], Fd, 5, 1.0), (zero, Ce[1], Fdv, 5, 1.0),
              (arr.nodal_mass, MeT, Fda, 5, 1.0))
    Z[:] = 0.0
    for i in range(len(blocks)):
        diag, Ee, F, b, weight = blocks[i]
        nodal_product(arr, diag, Ee, F, tmp)
        Z[:, b * nd:(b + 1) * nd] += weight * tmp
    Z[:, 6 * nd:] = r.T
    lu_solve_transposed_many(LU, piv, Z)  # F_d^T Z = E_d^T J^-T Z, E_d = rhs_q[:, n_r:]
    P = np.zeros((nd, 6 * nd + 3))
    E = arr.rhs_q
    for row in range(n):
        for c in range(nd):
            e = E[row, arr.n_input + c]
            if e != 0.0:
                P[c] += e * Z[row]
    Mb[:] = P[:, :nd]
    for c in range(2):
        Cb[c] = P[:, (1 + c) * nd:(2 + c) * nd]
    for k in range(3):
        Kb[k] = P[:, (3 + k) * nd:(4 + k) * nd]
    fd[:] = P[:, 6 * nd:].T
