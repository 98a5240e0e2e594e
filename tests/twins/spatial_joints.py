"""Plain-NumPy twins of the spatial joint kernels (rotation helpers, Euler normalization,
spatial truss, spatial hinge, rigid link, rigid-body inertia), written independently of
them: quaternion algebra as 4x4 matrices, closed-form chord derivatives, and
complex-step gradients of the twins' mode functions. Needs NumPy only (no pytest)."""

import numpy as np

__all__ = ["quat_twin", "conj_twin", "rotation_twin", "g_twin", "truss_twin", "hinge_modes_twin",
           "link_modes_twin", "rigid_body_twin", "complex_step"]


def quat_twin(a, b):
    """Quaternion product a b as the left-multiplication matrix of a applied to b."""
    a0, a1, a2, a3 = a
    L = np.array([[a0, -a1, -a2, -a3], [a1, a0, -a3, a2], [a2, a3, a0, -a1], [a3, -a2, a1, a0]])
    return L @ b


def conj_twin(a):
    return np.concatenate([a[:1], -a[1:]])


def rotation_twin(lam):
    """R with columns lam (0, e_i) conj(lam), the body axes in global components."""
    return np.stack([quat_twin(quat_twin(lam, np.r_[0.0, np.eye(3)[i]]), conj_twin(lam))[1:] for i in range(3)],
                    axis=1)


def g_twin(lam):
    """G (3,4) from Omega = 2 vec(conj(lam) lam') (body angular velocity), column by column."""
    return np.stack([quat_twin(conj_twin(lam), np.eye(4)[k])[1:] for k in range(4)], axis=1)


def truss_twin(xe, l0):
    """Elongation of a 3-D bar and its derivatives up to third order w.r.t. xe (6,)."""
    u = xe[3:] - xe[:3]
    l = np.linalg.norm(u)
    I = np.eye(3)
    d1 = u / l
    d2 = (I - np.outer(u, u) / l**2) / l
    d3 = (-(np.einsum("ij,k->ijk", I, u) + np.einsum("ik,j->ijk", I, u) + np.einsum("jk,i->ijk", I, u)) / l**3
          + 3 * np.einsum("i,j,k->ijk", u, u, u) / l**5)
    P = np.hstack([-I, I])
    return l - l0, P.T @ d1, P.T @ d2 @ P, np.einsum("abc,ai,bj,ck->ijk", d3, P, P, P)


def truss_inertia_twin(ae, rho_a_l0, gravity):
    """Mass matrix (2 dim, 2 dim) and ``M ae - f_gravity`` (2 dim,) of a uniform bar of mass
    rho_a_l0 (kg) with linearly interpolated position, by 2-point Gauss quadrature of
    int N_i N_j ds and int N_i ds in dim = len(gravity) dimensions."""
    dim = len(gravity)
    s = 0.5 + np.array([-0.5, 0.5]) / np.sqrt(3.0)
    N = np.stack([1 - s, s])  # (node, Gauss point)
    mass = rho_a_l0 * 0.5 * N @ N.T
    weights = rho_a_l0 * 0.5 * N.sum(axis=1)
    M = np.kron(mass, np.eye(dim))
    return M, M @ ae - np.kron(weights, gravity)


def hinge_modes_twin(xe, par):
    """(rotation, misalignment_2, misalignment_3) of the hinge; complex inputs allowed
    (the rotation as 4 atan(r1 / (|(r0, r1)| + r0)), equal to 2 atan2(r1, r0))."""
    p = quat_twin(xe[:4], par[:4])
    q = quat_twin(xe[4:], par[4:])
    r = quat_twin(conj_twin(p), q)
    angle = 4 * np.arctan(r[1] / (np.sqrt(r[0] ** 2 + r[1] ** 2) + r[0]))
    return np.array([angle, 2 * r[2], 2 * r[3]])


def link_modes_twin(xe, d):
    """x_b - x_a - R(lam) d for xe = [x_a, lam, x_b] (complex allowed)."""
    return xe[7:10] - xe[0:3] - rotation_twin(xe[3:7]) @ d


def complex_step(fun, x, h=1e-30):
    """Jacobian of a real-analytic fun at x (derivative index last) by the complex step."""
    cols = [np.imag(fun(x + 1j * h * e)) / h for e in np.eye(x.size)]
    return np.stack(cols, axis=-1)


def rigid_body_twin(lam, v, a, J):
    """M, r of T = 1/2 Omega^T J Omega, Omega = 2 G(lam) lam', from Lagrange's equations
    written with explicit matrices: r = d/dt(dT/dlam') - dT/dlam."""
    G, Gv = g_twin(lam), g_twin(v)
    M = 4 * G.T @ J @ G
    Om = 2 * G @ v
    # d/dt (2 G^T J Omega) = 2 Gv^T J Omega + 2 G^T J (2 Gv v + 2 G a); dT/dlam = 2 (d(G v)/dlam)^T J Omega
    dGv_dlam = np.stack([g_twin(np.eye(4)[k]) @ v for k in range(4)], axis=1)  # (3,4)
    r = 2 * Gv.T @ J @ Om + 2 * G.T @ J @ (2 * Gv @ v + 2 * G @ a) - 2 * dGv_dlam.T @ J @ Om
    return M, r
