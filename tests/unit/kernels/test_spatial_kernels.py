"""Spatial joint kernels (rotation helpers, Euler normalization, spatial truss, spatial
hinge, rigid link, rigid-body inertia) against the plain-NumPy twins of
tests/twins/spatial_joints.py (~1e-13) and finite differences of every derivative order."""

import numpy as np

from periodyn.kernels.elements import rigid_body, rotation, spatial_joints, spatial_truss
from tests.twins.spatial_joints import (complex_step, conj_twin, g_twin, hinge_modes_twin, link_modes_twin,
                                        quat_twin, rigid_body_twin, rotation_twin, truss_inertia_twin, truss_twin)

RNG = np.random.default_rng(11)


def _unit(v):
    return v / np.linalg.norm(v)


def _fd(fun, x, h):
    """Central differences of fun (array-valued) w.r.t. x, derivative index last."""
    return np.stack([(fun(x + h * e) - fun(x - h * e)) / (2 * h) for e in np.eye(x.size)], axis=-1)


def _modes(kernel, xe, par, nm):
    n = xe.size
    D, Dx, Dxx, Dxxx = np.zeros(nm), np.zeros((nm, n)), np.zeros((nm, n, n)), np.zeros((nm, n, n, n))
    kernel(xe, par, D, Dx, Dxx, Dxxx)
    return D, Dx, Dxx, Dxxx


def _check_orders(kernel, xe, par, nm, h=1e-5, tol=2e-8):
    """Each derivative order against central differences of the order below."""
    got = _modes(kernel, xe, par, nm)
    for order in range(1, 4):
        fd = _fd(lambda x: _modes(kernel, x, par, nm)[order - 1], xe, h)
        scale = max(1.0, np.abs(got[order]).max())
        np.testing.assert_allclose(got[order], fd, atol=tol * scale, err_msg=f"order {order}")
    return got


def test_rotation_helpers_match_twins():
    for _ in range(5):
        lam = _unit(RNG.standard_normal(4))
        R, G, prod = np.empty((3, 3)), np.empty((3, 4)), np.empty(4)
        rotation.rotation_matrix(lam, R)
        rotation.g_matrix(lam, G)
        np.testing.assert_allclose(R, rotation_twin(lam), atol=1e-14)
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
        np.testing.assert_allclose(G, g_twin(lam), atol=1e-15)
        b = RNG.standard_normal(4)
        rotation.product(lam, b, prod)
        np.testing.assert_allclose(prod, quat_twin(lam, b), atol=1e-14)
        # Omega = 2 G lam' is the body angular velocity: [Omega]x = R^T R' (R quadratic: central
        # differences are exact), for a lam' tangent to the unit sphere
        v = RNG.standard_normal(4)
        v -= (v @ lam) * lam
        Rdot = (rotation_twin(lam + 1e-3 * v) - rotation_twin(lam - 1e-3 * v)) / 2e-3
        W = R.T @ Rdot
        np.testing.assert_allclose(2 * G @ v, [W[2, 1], W[0, 2], W[1, 0]], atol=1e-12)
        np.testing.assert_allclose(G @ lam, 0, atol=1e-15)


def test_normalization_kernel():
    lam = RNG.standard_normal(4)
    D, Dx, Dxx, Dxxx = _check_orders(spatial_joints.normalization, lam, np.zeros(1), 1)
    np.testing.assert_allclose(D, [lam @ lam - 1], atol=1e-14)
    np.testing.assert_allclose(Dx[0], 2 * lam, atol=1e-14)
    np.testing.assert_allclose(Dxx[0], 2 * np.eye(4), atol=1e-14)
    np.testing.assert_allclose(Dxxx, 0, atol=1e-14)


def test_spatial_truss_matches_twin():
    xe = RNG.standard_normal(6)
    got = _check_orders(spatial_truss.deformation, xe, np.array([0.7]), 1)
    for g, t in zip(got, truss_twin(xe, 0.7)):
        np.testing.assert_allclose(g[0], t, atol=1e-13 * max(1, np.abs(t).max()))


def test_spatial_truss_inertia_matches_twin():
    """The bar's consistent mass in 3-D: M = kron(mass, I3), r = M a - weights g, no C, K."""
    rho_a_l0, gravity = 1.7, np.array([0.3, -9.81, 0.5])
    s = 0.5 + np.array([-0.5, 0.5]) / np.sqrt(3.0)
    ipar = np.r_[(1.7 * 0.5 * np.stack([1 - s, s]) @ np.stack([1 - s, s]).T).ravel(), 0.85, 0.85]
    xe, ve, ae = RNG.standard_normal((3, 6))
    M, r, C, K = np.zeros((6, 6)), np.zeros(6), np.zeros((6, 6)), np.zeros((6, 6))
    spatial_truss.inertia(xe, ve, ae, ipar, gravity, M, r, C, K)
    M_twin, r_twin = truss_inertia_twin(ae, rho_a_l0, gravity)
    np.testing.assert_allclose(M, M_twin, atol=1e-14)
    np.testing.assert_allclose(r, r_twin, atol=1e-13)
    np.testing.assert_allclose(M[:3, :3], 1.7 / 3 * np.eye(3), atol=1e-14)  # the textbook rho A l / 3
    assert not C.any() and not K.any()


def _hinge_state():
    axis = _unit(RNG.standard_normal(3))
    from periodyn.model.spatial import SpatialHinge
    lp, lq = _unit(RNG.standard_normal(4)), _unit(RNG.standard_normal(4))
    par = SpatialHinge("h", ("p", "q"), tuple(axis), ("free", "rigid", "rigid")).parameters(np.r_[lp, lq])
    # perturb both nodes (not normalized: the kernel must hold off the unit sphere too)
    return np.r_[lp, lq] + 0.05 * RNG.standard_normal(8), par, lp, lq, axis


def test_hinge_matches_twin_and_differences():
    for _ in range(4):
        xe, par, *_ = _hinge_state()
        D, Dx, Dxx, Dxxx = _check_orders(spatial_joints.hinge, xe, par, 3)
        np.testing.assert_allclose(D, hinge_modes_twin(xe, par), atol=1e-13)
        np.testing.assert_allclose(Dx, complex_step(lambda x: hinge_modes_twin(x, par), xe), atol=1e-13)
        np.testing.assert_allclose(Dxx, _fd(lambda x: complex_step(lambda y: hinge_modes_twin(y, par), x), xe, 1e-5),
                                   atol=1e-8)


def test_hinge_modes_measure_rotation_about_the_axis():
    """q turned by phi about the hinge axis relative to p: rotation = phi, misalignments 0;
    turned about a normal axis by a small angle b: misalignment of size 2 sin(b/2)."""
    _, par, lp, lq, axis = _hinge_state()
    for phi in (-2.5, 0.3, 1.7, 3.5, 6.0):
        turn = np.r_[np.cos(phi / 2), np.sin(phi / 2) * axis]
        lq_t = quat_twin(turn, lq)  # global rotation about the axis, applied after the reference
        lp_t = lp
        D = _modes(spatial_joints.hinge, np.r_[lp_t, lq_t], par, 3)[0]
        np.testing.assert_allclose(D, [phi, 0, 0], atol=1e-13)
    normal = _unit(np.cross(axis, RNG.standard_normal(3)))
    b = 0.01
    D = _modes(spatial_joints.hinge, np.r_[lp, quat_twin(np.r_[np.cos(b / 2), np.sin(b / 2) * normal], lq)], par, 3)[0]
    np.testing.assert_allclose(D[0], 0, atol=1e-13)
    np.testing.assert_allclose(np.hypot(D[1], D[2]), 2 * np.sin(b / 2), rtol=1e-12)


def test_rigid_link_matches_twin_and_differences():
    d = RNG.standard_normal(3)
    xe = RNG.standard_normal(10)
    D, Dx, Dxx, Dxxx = _check_orders(spatial_joints.rigid_link, xe, d, 3)
    np.testing.assert_allclose(D, link_modes_twin(xe, d), atol=1e-13)
    np.testing.assert_allclose(Dx, complex_step(lambda x: link_modes_twin(x, d), xe), atol=1e-13)


def _body(lam, v, a, J):
    M, r, C, K = np.zeros((4, 4)), np.zeros(4), np.zeros((4, 4)), np.zeros((4, 4))
    rigid_body.inertia(lam, v, a, J.ravel().copy(), np.zeros(3), M, r, C, K)
    return M, r, C, K


def test_rigid_body_inertia_matches_twin_euler_equations_and_differences():
    A = RNG.standard_normal((3, 3))
    J = A @ A.T + np.eye(3)
    lam, v, a = RNG.standard_normal(4), RNG.standard_normal(4), RNG.standard_normal(4)
    M, r, C, K = _body(lam, v, a, J)
    Mt, rt = rigid_body_twin(lam, v, a, J)
    np.testing.assert_allclose(M, Mt, atol=1e-13 * np.abs(Mt).max())
    np.testing.assert_allclose(r, rt, atol=1e-13 * np.abs(rt).max())
    np.testing.assert_allclose(_fd(lambda x: _body(lam, v, x, J)[1], a, 1e-3), M, atol=1e-10)
    np.testing.assert_allclose(_fd(lambda x: _body(lam, x, a, J)[1], v, 1e-4), C, atol=1e-8)
    np.testing.assert_allclose(_fd(lambda x: _body(x, v, a, J)[1], lam, 1e-5), K, atol=1e-8)
    # on the unit sphere with consistent rates, r = 2 G^T (J Omega' + Omega x J Omega) (Euler's equations)
    # up to a multiple of lam (the normalization's reaction)
    lam = _unit(lam)
    v -= (v @ lam) * lam
    a -= (a @ lam + v @ v) * lam  # second derivative of lam . lam = 1
    G = g_twin(lam)
    Om, Omdot = 2 * G @ v, 2 * G @ a  # G(v) v = 0
    torque = J @ Omdot + np.cross(Om, J @ Om)
    r = _body(lam, v, a, J)[1]
    tangent = np.eye(4) - np.outer(lam, lam)
    np.testing.assert_allclose(tangent @ r, 2 * G.T @ torque, atol=1e-12 * np.abs(r).max())


def test_twin_helpers_are_consistent():
    """conj and product of the twins: lam conj(lam) = 1 on the unit sphere."""
    lam = _unit(RNG.standard_normal(4))
    np.testing.assert_allclose(quat_twin(lam, conj_twin(lam)), [1, 0, 0, 0], atol=1e-15)
