"""Plain-NumPy twins of the planar multibody kernels, written independently of them
(closed-form chord derivatives, einsum assembly). Used by tests/unit/kernels/test_planar_kernels.py
and by benchmarks/bench_linearize.py, so this module needs NumPy and periodyn only (no pytest).
"""

import numpy as np

from periodyn.kernels.mechanism.assembly import reduced_sample

__all__ = ["chord_twin", "beam_deformation_twin", "beam_inertia_twin", "truss_deformation_twin", "elastic_twin",
           "midpoint_twin", "motion_twin", "kernel_sample"]


def chord_twin(u):
    """Length and angle of chord u (2,) with derivatives up to third order w.r.t. u."""
    l = np.hypot(*u)
    I = np.eye(2)
    l1 = u / l
    l2 = (I - np.outer(u, u) / l**2) / l
    l3 = (-(np.einsum("ij,k->ijk", I, u) + np.einsum("ik,j->ijk", I, u) + np.einsum("jk,i->ijk", I, u)) / l**3
          + 3 * np.einsum("i,j,k->ijk", u, u, u) / l**5)
    x, y = u
    a1 = np.array([-y, x]) / l**2
    a2 = np.array([[2 * x * y, y * y - x * x], [y * y - x * x, -2 * x * y]]) / l**4
    # third derivatives of atan2(y, x) (closed form)
    axxx = (2 * y * (y * y - 3 * x * x)) / l**6
    axxy = (2 * x * (x * x - 3 * y * y)) / l**6
    axyy = -axxx
    ayyy = -axxy
    a3 = np.array([[[axxx, axxy], [axxy, axyy]], [[axxy, axyy], [axyy, ayyy]]])
    return l, np.arctan2(y, x), (l1, l2, l3), (a1, a2, a3)


def _lift(P, d1, d2, d3):
    """Map derivatives w.r.t. u = P xe to derivatives w.r.t. xe."""
    return P.T @ d1, P.T @ d2 @ P, np.einsum("abc,ai,bj,ck->ijk", d3, P, P, P)


def beam_deformation_twin(xe, par):
    l0, cp, cq = par
    P = np.zeros((2, 6))
    P[0, 0], P[1, 1], P[0, 3], P[1, 4] = -1, -1, 1, 1
    l, alpha, ld, ad = chord_twin(P @ xe)
    L1, L2, L3 = _lift(P, *ld)
    A1, A2, A3 = _lift(P, *ad)
    wrap = lambda a: (a + np.pi) % (2 * np.pi) - np.pi
    th = np.array([wrap(xe[2] + cp - alpha), wrap(xe[5] + cq - alpha)])
    E = np.zeros((2, 6))
    E[0, 2], E[1, 5] = 1, 1
    T1 = E - A1
    Q = l0 / 30 * np.array([[4.0, -1.0], [-1.0, 4.0]])
    g = Q @ th
    D = np.array([l - l0 + 0.5 * th @ Q @ th, th[0], th[1]])
    Dx = np.vstack([L1 + g @ T1, T1])
    Dxx = np.stack([L2 + T1.T @ Q @ T1 - g.sum() * A2, -A2, -A2])
    QT = Q.sum(axis=0) @ T1  # sum_k Q[k, m] T1[m] ... symmetric in k, m
    cross = (np.einsum("ac,b->abc", A2, QT) + np.einsum("bc,a->abc", A2, QT) + np.einsum("ab,c->abc", A2, QT))
    Dxxx = np.stack([L3 - cross - g.sum() * A3, -A3, -A3])
    return D, Dx, Dxx, Dxxx


def beam_inertia_twin(xe, ve, ae, mass, weights, rotary, gravity, par):
    """Returns M (6,6), r = M a - f (6,), C = dr/dve, K = dr/dxe."""
    l0, cp, cq = par
    G = np.zeros((4, 2, 6))
    G[0][:, [0, 1]] = np.eye(2)
    G[1][:, [3, 4]] = np.eye(2)
    gdd = np.zeros((4, 2))
    gdd[0], gdd[1] = ae[[0, 1]], ae[[3, 4]]
    H = np.zeros((4, 2, 6))
    Pd = np.zeros((4, 2, 6))
    dG = np.zeros((4, 2, 6))  # d(G_i column)/d(angle)
    for k, col in enumerate((2, 5)):
        psi = xe[col] + par[1 + k]
        t, n = np.array([np.cos(psi), np.sin(psi)]), np.array([-np.sin(psi), np.cos(psi)])
        w, acc = ve[col], ae[col]
        G[2 + k][:, col] = l0 * n
        dG[2 + k][:, col] = -l0 * t
        gdd[2 + k] = l0 * (acc * n - w * w * t)
        H[2 + k][:, col] = -2 * l0 * w * t
        Pd[2 + k][:, col] = l0 * (-acc * t - w * w * n)
    M = np.einsum("ij,ica,jcb->ab", mass, G, G)
    B = mass @ gdd - np.outer(weights, gravity)
    r = np.einsum("ica,ic->a", G, B)
    C = np.einsum("ij,ica,jcb->ab", mass, G, H)
    K = np.einsum("ij,ica,jcb->ab", mass, G, Pd) + np.diag(np.einsum("ica,ic->a", dG, B))
    # rotary inertia of the sections: h = (alpha, phi_p, phi_q)
    P = np.zeros((2, 6))
    P[0, 0], P[1, 1], P[0, 3], P[1, 4] = -1, -1, 1, 1
    _, _, _, (a1, a2, a3) = chord_twin(P @ xe)
    A1, A2, A3 = _lift(P, a1, a2, a3)
    Hg = np.zeros((3, 6))
    Hg[0], Hg[1, 2], Hg[2, 5] = A1, 1, 1
    hdd = Hg @ ae + np.array([ve @ A2 @ ve, 0, 0])
    Br = rotary @ hdd
    M = M + Hg.T @ rotary @ Hg
    r = r + Hg.T @ Br
    C = C + np.outer(Hg.T @ rotary[:, 0], 2 * A2 @ ve)
    K = K + A2 * Br[0] + np.outer(Hg.T @ rotary[:, 0], A2 @ ae + np.einsum("abc,b,c->a", A3, ve, ve))
    return M, r, C, K


def truss_deformation_twin(xe, par):
    P = np.array([[-1.0, 0, 1, 0], [0, -1, 0, 1]])
    l, _, ld, _ = chord_twin(P @ xe)
    L1, L2, L3 = _lift(P, *ld)
    return np.array([l - par[0]]), L1[None], L2[None], L3[None]


def elastic_twin(D, Dx, Dxx, ve, S, Sd, s0=0.0):
    """r = Dx^T sigma, C, K of the Kelvin-Voigt law with constant stress s0 (see
    periodyn.kernels.elements.elastic)."""
    rate = Dx @ ve
    sigma = S @ D + Sd @ rate + s0
    rate_x = np.einsum("kac,c->ka", Dxx, ve)
    r = Dx.T @ sigma
    C = Dx.T @ Sd @ Dx
    K = Dx.T @ S @ Dx + Dx.T @ Sd @ rate_x + np.einsum("m,mab->ab", sigma, Dxx)
    return r, C, K


def midpoint_twin(xe, L):
    a, m, b = xe[0:2], xe[2:4], xe[4:6]
    u = b - a
    return (u[0] * (m - a)[1] - u[1] * (m - a)[0]) / (np.hypot(*u) * L)


def motion_twin(model, x, qdot, qddot):
    """NumPy twin of kernels.transfer.motion + assembly.nodal_arrays + reduced_sample for planar
    beams (the slider-crank); returns Mb, Cb, Kb, fd."""
    arr = model.arrays
    n = x.size
    tensors = []
    J = np.zeros((n, n))
    for i in np.nonzero(arr.coord_row >= 0)[0]:
        J[arr.coord_row[i], i] = 1
    for e in range(arr.family.size):
        assert arr.family[e] == 0
        idx = arr.dofs[e]
        t = beam_deformation_twin(x[idx], arr.par[e])
        tensors.append(t)
        for k in range(3):
            row = arr.mode_row[arr.modes[e, k]]
            if row >= 0:
                J[row, idx] += t[1][k]

    def contract(order, *vectors):
        """Order-th derivative tensors of the deformations contracted with vectors, (n,)."""
        out = np.zeros(n)
        for e, t in enumerate(tensors):
            idx = arr.dofs[e]
            for k in range(3):
                row = arr.mode_row[arr.modes[e, k]]
                if row >= 0:
                    out[row] = np.einsum(t[order][k], list(range(order)), *[a for i, v in enumerate(vectors)
                                                                        for a in (v[idx], [i])])
        return out

    def phi2(u, w):
        return contract(2, u, w)

    def phi3(u, w, z):
        return contract(3, u, w, z)

    Fq = np.linalg.solve(J, arr.rhs_q)
    nr = arr.n_input
    Fd = Fq[:, nr:]
    nd = Fd.shape[1]
    v = Fq @ qdot
    a = np.linalg.solve(J, arr.rhs_q @ qddot - phi2(v, v))
    Fdv = -np.linalg.solve(J, np.stack([phi2(Fd[:, i], v) for i in range(nd)], axis=1))
    Fdd = -np.linalg.solve(J, np.stack([np.stack([phi2(Fd[:, i], Fd[:, j]) for j in range(nd)], 1)
                                        for i in range(nd)], 1).reshape(n, -1)).reshape(n, nd, nd)
    Fda = -np.linalg.solve(J, np.stack([phi3(Fd[:, i], v, v) + phi2(Fd[:, i], a) + 2 * phi2(Fdv[:, i], v)
                                        for i in range(nd)], axis=1))
    M = np.diag(arr.nodal_mass)
    r = arr.nodal_mass * a - arr.nodal_force
    C = np.zeros((n, n))
    K = np.zeros((n, n))
    for e, t in enumerate(tensors):
        idx = arr.dofs[e]
        ip = arr.ipar[e]  # planar beam layout: [l0, c_p, c_q, mass 4x4, weights 4, rotary 3x3]
        Me, re, Ce, Ke = beam_inertia_twin(x[idx], v[idx], a[idx], ip[3:19].reshape(4, 4), ip[19:23],
                                           ip[23:32].reshape(3, 3), arr.gravity, arr.par[e])
        rel, Cel, Kel = elastic_twin(t[0], t[1], t[2], v[idx], arr.stiffness[e], arr.damping[e], arr.stress0[e])
        ix = np.ix_(idx, idx)
        M[ix] += Me
        C[ix] += Ce + Cel
        K[ix] += Ke + Kel
        np.add.at(r, idx, re + rel)
    Mb = Fd.T @ M @ Fd
    Cb = Fd.T @ C @ Fd + 2 * Fd.T @ M @ Fdv
    Kb = np.einsum("k,kij->ij", r, Fdd) + Fd.T @ K @ Fd + Fd.T @ M @ Fda + Fd.T @ C @ Fdv
    return Mb, Cb, Kb, Fd.T @ r


def kernel_sample(model, x, qdot, qddot):
    n, nd = model.n_coordinates, model.n_dynamic
    out = [np.empty((nd, nd)), np.empty((nd, nd)), np.empty((nd, nd)), np.empty(nd)]
    reduced_sample(model.arrays, x, qdot, qddot, np.zeros(n), *out, np.empty((n, nd)), np.empty((n, nd)), np.empty((n, nd)))
    return out
