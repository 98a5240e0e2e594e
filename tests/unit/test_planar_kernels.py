"""Planar multibody kernels against plain-NumPy twins (~1e-13) and finite differences.

The twins below are written independently of the kernels (closed-form chord
derivatives, einsum assembly) and are also used by benchmarks/bench_linearize.py.
"""

import numpy as np
import pytest

from periodyn.examples.slider_crank import slider_crank_model
from periodyn.kernels import elastic, outputs, planar_beam, planar_hinge, planar_truss
from periodyn.kernels.assembly import reduced_sample
from periodyn.kinematics import nominal_configurations
from periodyn.model import PlanarBeam

RNG = np.random.default_rng(7)
HERMITE_MASS = np.array([[13 / 35, 9 / 70, 11 / 210, -13 / 420], [9 / 70, 13 / 35, 13 / 420, -11 / 210],
                         [11 / 210, 13 / 420, 1 / 105, -1 / 140], [-13 / 420, -11 / 210, -1 / 140, 1 / 105]])
HERMITE_WEIGHTS = np.array([0.5, 0.5, 1 / 12, -1 / 12])


# ----------------------------------------------------------------------------- twins
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


def elastic_twin(D, Dx, Dxx, ve, S, Sd):
    """r = Dx^T sigma, C, K of the Kelvin-Voigt law (see periodyn.kernels.elastic)."""
    rate = Dx @ ve
    sigma = S @ D + Sd @ rate
    rate_x = np.einsum("kac,c->ka", Dxx, ve)
    r = Dx.T @ sigma
    C = Dx.T @ Sd @ Dx
    K = Dx.T @ S @ Dx + Dx.T @ Sd @ rate_x + np.einsum("m,mab->ab", sigma, Dxx)
    return r, C, K


def midpoint_twin(xe, L):
    a, m, b = xe[0:2], xe[2:4], xe[4:6]
    u = b - a
    return (u[0] * (m - a)[1] - u[1] * (m - a)[0]) / (np.hypot(*u) * L)


# ----------------------------------------------------------------------------- helpers
def _kernel_deformation(kernel, xe, par, nm, nx):
    D, Dx, Dxx, Dxxx = np.zeros(3), np.zeros((3, 6)), np.zeros((3, 6, 6)), np.zeros((3, 6, 6, 6))
    kernel(xe, par, D, Dx, Dxx, Dxxx)
    return D[:nm], Dx[:nm, :nx], Dxx[:nm, :nx, :nx], Dxxx[:nm, :nx, :nx, :nx]


def _beam_state():
    xe = np.array([0.1, -0.2, 0.3, 0.45, 0.05, 0.2]) + 0.01 * RNG.standard_normal(6)
    l0 = 0.42
    par = np.array([l0, 0.05, -0.1])
    return xe, par


def _fd(fun, x, h):
    """Central differences of fun (array-valued) w.r.t. x, derivative index last."""
    cols = []
    for i in range(x.size):
        e = np.zeros_like(x)
        e[i] = h
        cols.append((fun(x + e) - fun(x - e)) / (2 * h))
    return np.stack(cols, axis=-1)


# ----------------------------------------------------------------------------- twin tests
def test_beam_deformation_matches_twin():
    for _ in range(5):
        xe, par = _beam_state()
        got = _kernel_deformation(planar_beam.deformation, xe, par, 3, 6)
        for g, t in zip(got, beam_deformation_twin(xe, par)):
            np.testing.assert_allclose(g, t, rtol=0, atol=1e-13 * max(1.0, np.abs(t).max()))


def test_beam_deformation_derivatives_by_finite_differences():
    xe, par = _beam_state()
    D, Dx, Dxx, Dxxx = _kernel_deformation(planar_beam.deformation, xe, par, 3, 6)
    k = lambda i: (lambda x: _kernel_deformation(planar_beam.deformation, x, par, 3, 6)[i])
    np.testing.assert_allclose(_fd(k(0), xe, 1e-6), Dx, atol=1e-8)
    np.testing.assert_allclose(_fd(k(1), xe, 1e-6), Dxx, atol=1e-7)
    np.testing.assert_allclose(_fd(k(2), xe, 1e-6), Dxxx, atol=2e-6)


def test_beam_bowing_is_zero_for_rigid_motion_and_matches_arc_length():
    """D = 0 for any rigid motion of the reference; the elongation includes the arc-length
    excess l0 (2 tp^2 - tp tq + 2 tq^2)/30 of the Hermite deflection line."""
    par = np.array([0.5, 0.0, 0.0])
    for angle in (0.3, 2.5, -2.9):
        c, s = np.cos(angle), np.sin(angle)
        xe = np.array([1.0, 2.0, angle, 1.0 + 0.5 * c, 2.0 + 0.5 * s, angle])
        D = _kernel_deformation(planar_beam.deformation, xe, par, 3, 6)[0]
        np.testing.assert_allclose(D, 0.0, atol=1e-14)
    tp, tq = 0.02, -0.015
    s = np.linspace(0, 1, 20001)
    slope = tp * (1 - 4 * s + 3 * s**2) + tq * (-2 * s + 3 * s**2)
    arc = 0.5 * np.trapezoid(np.sqrt(1 + slope**2), s)
    xe = np.array([0.0, 0.0, tp, arc * 0 + 0.5 - 0.5 / 30 * (2 * tp**2 - tp * tq + 2 * tq**2), 0.0, tq])
    D = _kernel_deformation(planar_beam.deformation, xe, par, 3, 6)[0]
    assert D[0] == pytest.approx(0.0, abs=1e-15)
    assert 0.5 - xe[3] == pytest.approx(arc - 0.5, rel=1e-3)  # chord shortening = arc excess


def test_beam_inertia_matches_twin_and_derivatives():
    xe, par = _beam_state()
    ve, ae = RNG.standard_normal(6), RNG.standard_normal(6)
    mass, weights = 0.3 * HERMITE_MASS, 0.3 * HERMITE_WEIGHTS
    rotary = PlanarBeam("b", ("p", "q"), ("a", "b"), ("rigid",) * 3, rotary_inertia_per_length=0.02).rotary(par[0])
    gravity = np.array([0.3, -9.81])

    def kernel(x, v, a):
        out = [np.zeros((6, 6)), np.zeros(6), np.zeros((6, 6)), np.zeros((6, 6))]
        planar_beam.inertia(x, v, a, mass, weights, rotary, gravity, par, *out)
        return out

    got = kernel(xe, ve, ae)
    for g, t in zip(got, beam_inertia_twin(xe, ve, ae, mass, weights, rotary, gravity, par)):
        np.testing.assert_allclose(g, t, atol=1e-13 * max(1, np.abs(t).max()))
    M, r, C, K = got
    np.testing.assert_allclose(_fd(lambda a: kernel(xe, ve, a)[1], ae, 1e-3), M, atol=1e-10)
    np.testing.assert_allclose(_fd(lambda v: kernel(xe, v, ae)[1], ve, 1e-4), C, atol=1e-9)
    np.testing.assert_allclose(_fd(lambda x: kernel(x, ve, ae)[1], xe, 1e-6), K, atol=1e-8)
    np.testing.assert_allclose(M, M.T, atol=1e-15)


def _reference_beam_mass(l0, rhoA, rhoI):
    beam = PlanarBeam("b", ("p", "q"), ("a", "b"), ("rigid",) * 3, mass_per_length=rhoA,
                      rotary_inertia_per_length=rhoI)
    mass, weights = beam.inertia(l0)
    M = np.zeros((6, 6))
    planar_beam.inertia(np.array([0, 0, 0, l0, 0, 0.0]), np.zeros(6), np.zeros(6), mass, weights, beam.rotary(l0),
                        np.zeros(2), np.array([l0, 0, 0.0]), M, np.zeros(6), np.zeros((6, 6)), np.zeros((6, 6)))
    return M, weights


def test_beam_mass_is_the_hermite_consistent_mass():
    """In the reference (axis along x) the lateral block equals the textbook matrix
    rhoA l/420 [156, 22l, 54, -13l; ...] with rotations as coordinates, and the rotary
    inertia adds the textbook rhoI/(30 l) [36, 3l, -36, 3l; ...]."""
    l0, rhoA, rhoI = 0.15, 0.2225, 3e-4
    lat = [1, 2, 4, 5]
    book = rhoA * l0 / 420 * np.array([[156, 22 * l0, 54, -13 * l0], [22 * l0, 4 * l0**2, 13 * l0, -3 * l0**2],
                                       [54, 13 * l0, 156, -22 * l0], [-13 * l0, -3 * l0**2, -22 * l0, 4 * l0**2]])
    M, weights = _reference_beam_mass(l0, rhoA, 0.0)
    np.testing.assert_allclose(M[np.ix_(lat, lat)], book, rtol=1e-13)
    np.testing.assert_allclose(weights, rhoA * l0 * HERMITE_WEIGHTS, rtol=1e-13)
    rot = rhoI / (30 * l0) * np.array([[36, 3 * l0, -36, 3 * l0], [3 * l0, 4 * l0**2, -3 * l0, -l0**2],
                                       [-36, -3 * l0, 36, -3 * l0], [3 * l0, -l0**2, -3 * l0, 4 * l0**2]])
    M_rot, _ = _reference_beam_mass(l0, rhoA, rhoI)
    np.testing.assert_allclose(M_rot[np.ix_(lat, lat)], book + rot, rtol=1e-12, atol=1e-16)


def test_truss_and_hinge_match_twins():
    xe = np.array([0.1, 0.2, 0.7, -0.1])
    par = np.array([0.6, 0, 0])
    got = _kernel_deformation(planar_truss.deformation, xe, par, 1, 4)
    for g, t in zip(got, truss_deformation_twin(xe, par)):
        np.testing.assert_allclose(g, t, atol=1e-14)
    np.testing.assert_allclose(_fd(lambda x: _kernel_deformation(planar_truss.deformation, x, par, 1, 4)[1], xe, 1e-6),
                               got[2], atol=1e-8)
    mass = 0.5 * np.array([[1 / 3, 1 / 6], [1 / 6, 1 / 3]])
    M, r = np.zeros((4, 4)), np.zeros(4)
    ae = RNG.standard_normal(4)
    planar_truss.inertia(xe, np.zeros(4), ae, mass, np.array([0.25, 0.25]), np.zeros((3, 3)), np.array([0, -9.81]), par, M, r,
                         np.zeros((4, 4)), np.zeros((4, 4)))
    np.testing.assert_allclose(M, np.kron(mass, np.eye(2)), atol=1e-15)
    np.testing.assert_allclose(r, M @ ae - np.array([0, -0.25 * 9.81, 0, -0.25 * 9.81]), atol=1e-14)
    D, Dx, Dxx, Dxxx = _kernel_deformation(planar_hinge.deformation, np.array([0.3, 7.5]), np.array([0.2, 0, 0]), 1, 2)
    np.testing.assert_allclose(D, [7.0], atol=1e-15)  # not wrapped
    np.testing.assert_allclose(Dx, [[-1.0, 1.0]])


def test_elastic_matches_twin_and_derivatives():
    xe, par = _beam_state()
    ve = RNG.standard_normal(6)
    S = np.zeros((3, 3))
    S[1:, 1:] = 30 * np.array([[4, 2], [2, 4.0]])
    S[0, 0] = 500.0
    Sd = 1e-3 * S

    def kernel(x, v):
        D, Dx, Dxx, _ = _kernel_deformation(planar_beam.deformation, x, par, 3, 6)
        r, C, K = np.zeros(6), np.zeros((6, 6)), np.zeros((6, 6))
        elastic.add_elastic(3, 6, D, Dx, Dxx, v, S, Sd, r, C, K)
        return r, C, K, (D, Dx, Dxx)

    r, C, K, (D, Dx, Dxx) = kernel(xe, ve)
    for g, t in zip((r, C, K), elastic_twin(D, Dx, Dxx, ve, S, Sd)):
        np.testing.assert_allclose(g, t, atol=1e-13 * max(1, np.abs(t).max()))
    np.testing.assert_allclose(_fd(lambda v: kernel(xe, v)[0], ve, 1e-4), C, atol=1e-9)
    np.testing.assert_allclose(_fd(lambda x: kernel(x, ve)[0], xe, 1e-7), K, rtol=1e-6, atol=1e-5)


def test_midpoint_deflection_matches_twin_and_gradient():
    xe = np.array([0.1, 0.0, 0.3, 0.02, 0.5, 0.01])
    grad = np.empty(6)
    y = outputs.midpoint_deflection(xe, 0.3, grad)
    assert y == pytest.approx(midpoint_twin(xe, 0.3), abs=1e-15)
    np.testing.assert_allclose(_fd(lambda x: np.array(midpoint_twin(x, 0.3)), xe, 1e-6), grad, atol=1e-8)


# ----------------------------------------------------------------------------- per-sample twin
def motion_twin(model, x, qdot, qddot):
    """NumPy twin of kernels.assembly.motion + nodal_arrays + reduced_sample for planar
    beams (the slider-crank); returns Mb, Cb, Kb, fd."""
    arr = model.arrays
    n = x.size
    rows = []
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

    def phi2(u, w):
        out = np.zeros(n)
        for e, t in enumerate(tensors):
            idx = arr.dofs[e]
            for k in range(3):
                row = arr.mode_row[arr.modes[e, k]]
                if row >= 0:
                    out[row] = u[idx] @ t[2][k] @ w[idx]
        return out

    def phi3(u, w, z):
        out = np.zeros(n)
        for e, t in enumerate(tensors):
            idx = arr.dofs[e]
            for k in range(3):
                row = arr.mode_row[arr.modes[e, k]]
                if row >= 0:
                    out[row] = np.einsum("abc,a,b,c->", t[3][k], u[idx], w[idx], z[idx])
        return out

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
        Me, re, Ce, Ke = beam_inertia_twin(x[idx], v[idx], a[idx], arr.mass[e], arr.weights[e], arr.rotary[e],
                                           arr.gravity, arr.par[e])
        rel, Cel, Kel = elastic_twin(t[0], t[1], t[2], v[idx], arr.stiffness[e], arr.damping[e])
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
    reduced_sample(model.arrays, x, qdot, qddot, *out, np.empty((n, nd)), np.empty((n, nd)), np.empty((n, nd)))
    return out


def test_per_sample_linearization_matches_numpy_twin():
    model = slider_crank_model(kelvin_voigt=5e-5, rotary_inertia_per_length=1e-4)
    X = nominal_configurations(model, 8)
    qdot = np.array([200.0, 0.3, -0.2, 0.1, 0.4])
    qddot = np.array([50.0, 1.0, 2.0, -1.0, 0.5])
    for x in X[[1, 3, 6]]:
        for g, t in zip(kernel_sample(model, x, qdot, qddot), motion_twin(model, x, qdot, qddot)):
            np.testing.assert_allclose(g, t, rtol=0, atol=1e-13 * np.abs(t).max())
