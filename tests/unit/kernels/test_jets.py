"""Taylor jets (kernels/jets.py): every operation against complex-step and central
finite differences, and against closed forms (planar chord, rotation matrices)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from periodyn.kernels.elements import jets, planar_geometry

RNG = np.random.default_rng(11)


def _seeds(x):
    """Jets of the coordinates x (n,) themselves, shape (n, size(n))."""
    n = x.size
    out = np.zeros((n, jets.size(n)))
    for i in range(n):
        jets.seed(x[i], i, out[i])
    return out


def _orders(J):
    v, g, H, T = jets.parts(J)
    return v[0], g.copy(), H.copy(), T.copy()


def _fd(fun, x, h=1e-5):
    """Central differences of fun (array-valued) w.r.t. x, derivative index last."""
    return np.stack([(np.asarray(fun(x + h * e)) - np.asarray(fun(x - h * e))) / (2 * h) for e in np.eye(x.size)],
                    axis=-1)


def _complex_step(fun, x, h=1e-30):
    """Gradient of the real function fun (written for complex input) by the complex step."""
    g = np.empty(x.size)
    for i in range(x.size):
        z = x.astype(complex)
        z[i] += 1j * h
        g[i] = fun(z).imag / h
    return g


def _check(jet_fun, cfun, x, tol=1e-7):
    """The jet of jet_fun at x: value = cfun, gradient = complex step of cfun to 1e-13
    (relative), Hessian and third derivatives = central differences of the jet's own lower
    orders."""
    v, g, H, T = _orders(jet_fun(x))
    assert v == pytest.approx(cfun(x.astype(complex)).real, rel=1e-14, abs=1e-14)
    np.testing.assert_allclose(g, _complex_step(cfun, x), rtol=1e-13, atol=1e-13 * max(1, abs(v)))
    np.testing.assert_allclose(H, _fd(lambda y: _orders(jet_fun(y))[1], x), rtol=tol, atol=tol)
    np.testing.assert_allclose(T, _fd(lambda y: _orders(jet_fun(y))[2], x), rtol=tol, atol=tol)
    np.testing.assert_allclose(H, H.T, atol=1e-14 * max(1, np.abs(H).max()))
    for perm in [(1, 0, 2), (0, 2, 1), (2, 1, 0)]:
        np.testing.assert_allclose(T, T.transpose(perm), atol=1e-13 * max(1, np.abs(T).max()))


def _sin(a):
    """sin of a jet through compose (a univariate function with its derivatives)."""
    out = np.empty_like(a)
    s, c = np.sin(a[0]), np.cos(a[0])
    jets.compose(a, s, c, -s, -c, out)
    return out


def _poly(s):
    """A non-polynomial-degree-3 jet of three coordinates: sin(x0 + 2 x1 x2) + x0 x1."""
    t = np.empty_like(s[0])
    jets.mul(s[1], s[2], t)
    jets.lincomb(1.0, s[0], 2.0, t, t)
    out = _sin(t)
    jets.mul(s[0], s[1], t)
    jets.add(out, t, out)
    return out


def _poly_c(z):
    return np.sin(z[0] + 2 * z[1] * z[2]) + z[0] * z[1]


X = np.array([0.3, -0.7, 1.1])


def test_seed_constant_and_parts():
    n = 3
    J = np.empty(jets.size(n))
    jets.seed(2.5, 1, J)
    v, g, H, T = jets.parts(J)
    assert jets.dim(J) == n and v[0] == 2.5
    np.testing.assert_array_equal(g, [0, 1, 0])
    assert not H.any() and not T.any()
    jets.constant(-4.0, J)
    assert J[0] == -4.0 and not J[1:].any()


def test_compose_and_add_scale():
    _check(lambda x: _poly(_seeds(x)), _poly_c, X)
    out = np.empty(jets.size(3))

    def f(x):
        s = _seeds(x)
        jets.scale(_poly(s), -3.0, out)
        jets.sub(out, s[2], out)
        return out.copy()
    _check(f, lambda z: -3 * _poly_c(z) - z[2], X)


def test_mul_leibniz():
    def f(x):
        s = _seeds(x)
        a = _poly(s)
        b = _sin(s[1])
        jets.mul(a, b, a)  # in place: out is an input
        return a
    _check(f, lambda z: _poly_c(z) * np.sin(z[1]), X)


def test_reciprocal_divide_sqrt():
    def recip(x):
        a = _poly(_seeds(x))
        jets.reciprocal(a, a)
        return a
    _check(recip, lambda z: 1 / _poly_c(z), X)

    def div(x):
        s = _seeds(x)
        a = _poly(s)
        b = _sin(s[2])
        jets.divide(b, a, a)
        return a
    _check(div, lambda z: np.sin(z[2]) / _poly_c(z), X)

    def root(x):
        a = _poly(_seeds(x))
        jets.lincomb(1.0, a, 0.0, a, a)
        a[0] += 3.0
        jets.sqrt(a, a)
        return a
    _check(root, lambda z: np.sqrt(_poly_c(z) + 3.0), X)


@pytest.mark.parametrize("centre", [(1.0, 0.2), (0.2, 1.0), (-1.0, 0.3), (-0.3, -1.0), (0.4, -1.0)])
def test_atan2_every_octant(centre):
    cx, cy = centre

    def f(x):
        s = _seeds(x)
        y = _poly(s)
        jets.lincomb(0.1, y, 0.0, y, y)
        y[0] += cy
        xx = _sin(s[0])
        jets.lincomb(0.1, xx, 0.0, xx, xx)
        xx[0] += cx
        out = np.empty_like(y)
        jets.atan2(y, xx, out)
        return out

    def branch(y, x):
        # arctan2 is not complex-analytic; near the point it equals a real-analytic
        # arctan of a ratio plus a constant
        return np.arctan(y / x) if abs(cx) >= abs(cy) else -np.arctan(x / y)

    y0, x0 = 0.1 * _poly_c(X) + cy, 0.1 * np.sin(X[0]) + cx
    shift = np.arctan2(y0, x0) - branch(y0, x0)
    _check(f, lambda z: branch(0.1 * _poly_c(z) + cy, 0.1 * np.sin(z[0]) + cx) + shift, X)


@pytest.mark.parametrize("u", [np.array([0.7, 0.2]), np.array([-0.1, 0.9]), np.array([-0.6, -0.5])])
def test_length_and_angle_match_planar_chord(u):
    """|u| = sqrt(u . u) and atan2 jets over the four planar chord coordinates equal the
    complex-number derivatives of planar_geometry.chord to 1e-13."""
    xe = np.array([0.2, -0.3, 0.0, 0.2 + u[0], -0.3 + u[1], 0.0])
    n = 6
    s = np.zeros((n, jets.size(n)))
    for i in range(n):
        jets.seed(xe[i], i, s[i])
    d = np.zeros((3, jets.size(n)))
    for c in range(2):
        jets.sub(s[3 + c], s[c], d[c])
    ll = np.empty(jets.size(n))
    jets.dot3(d, d, ll)
    jets.sqrt(ll, ll)
    ang = np.empty_like(ll)
    jets.atan2(d[1], d[0], ang)
    length, alpha, L1, L2, L3, A1, A2, A3 = planar_geometry.chord(xe, 0, 3, n)
    for J, ref in ((ll, (length, L1, L2, L3)), (ang, (alpha, A1, A2, A3))):
        for got, want in zip(_orders(J), ref):
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-13 * max(1, np.abs(want).max()))
    assert not _orders(ll)[1][[2, 5]].any()  # the angles' coordinates do not enter


def test_cross_matvec_and_embed():
    x = RNG.standard_normal(6)
    n = 6
    s = _seeds(x)
    u, v = s[:3], s[3:]
    w = np.zeros((3, jets.size(n)))
    jets.cross3(u, v, w)
    np.testing.assert_allclose([wi[0] for wi in w], np.cross(x[:3], x[3:]), atol=1e-15)
    # u . (u x v) = 0 with all its derivatives
    z = np.empty(jets.size(n))
    jets.dot3(u, w, z)
    assert np.abs(z).max() < 1e-13
    # matvec by a constant matrix: R u has gradient R on the u-coordinates
    A = RNG.standard_normal((3, 3))
    R = np.zeros((3, 3, jets.size(n)))
    for i in range(3):
        for j in range(3):
            jets.constant(A[i, j], R[i, j])
    jets.matvec3(R, u, w)
    for i in range(3):
        np.testing.assert_allclose(_orders(w[i])[1][:3], A[i], atol=1e-15)
    # embed: a jet over 3 coordinates lifted into 6 coordinates at positions (4, 0, 2)
    a = _poly(_seeds(X))
    big = np.empty(jets.size(n))
    index = np.array([4, 0, 2])
    jets.embed(a, index, big)
    y = np.zeros(6)
    y[index] = X
    ref = _poly(_seeds(y)[index])  # the same function of the same coordinates, computed over 6
    np.testing.assert_allclose(big, ref, atol=1e-14)


def _unit_quat():
    q = RNG.standard_normal(4)
    return q / np.linalg.norm(q)


def test_rotation_of_euler_parameters():
    lam = _unit_quat()
    R = np.zeros((3, 3, jets.size(4)))
    jets.rotation(_seeds(lam), R)
    Rv = R[:, :, 0]
    # scipy's quaternion is scalar-last (x, y, z, w)
    ref = Rotation.from_quat(np.r_[lam[1:], lam[0]]).as_matrix()
    np.testing.assert_allclose(Rv, ref, atol=1e-14)
    np.testing.assert_allclose(Rv @ Rv.T, np.eye(3), atol=1e-14)
    # the seeded (quadratic-form) version equals the generic product rule, embedded at offset 3
    n = 9
    Rs = np.zeros((3, 3, jets.size(n)))
    jets.rotation_seeded(lam, 3, Rs)
    x = np.r_[RNG.standard_normal(3), lam, RNG.standard_normal(2)]
    Rg = np.zeros_like(Rs)
    jets.rotation(_seeds(x)[3:7], Rg)
    np.testing.assert_allclose(Rs, Rg, atol=1e-15)
    # derivatives against differences of the matrix itself (quadratic: exact differences)
    Rfun = lambda q: Rotation.from_quat(np.r_[q[1:], q[0]] / np.linalg.norm(q)).as_matrix() * (q @ q)
    g = np.stack([jets.parts(R[i, j])[1] for i in range(3) for j in range(3)]).reshape(3, 3, 4)
    np.testing.assert_allclose(g, _fd(Rfun, lam, 1e-4), atol=1e-10)
    H = np.stack([jets.parts(R[i, j])[2] for i in range(3) for j in range(3)]).reshape(3, 3, 4, 4)
    np.testing.assert_allclose(H, _fd(lambda q: _fd(Rfun, q, 1e-3), lam, 1e-3), atol=1e-7)
    assert not any(jets.parts(R[i, j])[3].any() for i in range(3) for j in range(3))
