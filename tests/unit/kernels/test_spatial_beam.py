"""Spatial beam kernels against NumPy twins (~1e-13), finite differences, rigid motions,
the planar beam, and the geometry their second-order terms stand for."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from periodyn.errors import InputError
from periodyn.kernels.elements import planar_beam, spatial_beam
from periodyn.model.spatial_beam import BeamSection, SpatialBeam, beam_parameters, section_second_moments
from tests.twins.spatial import SLOPES, _gauss, HERMITE, beam_deformation_twin, beam_inertia_twin

RNG = np.random.default_rng(5)
N = spatial_beam.NDOF
GRAVITY = np.array([0.3, -9.81, 1.2])


def quat(R):
    q = Rotation.from_matrix(R).as_quat()
    return np.r_[q[3], q[:3]]


def rot(lam):
    return Rotation.from_quat(np.r_[lam[1:], lam[0]]).as_matrix()


def kernel_deformation(xe, par):
    D, Dx, Dxx, Dxxx = np.zeros(6), np.zeros((6, N)), np.zeros((6, N, N)), np.zeros((6, N, N, N))
    spatial_beam.deformation(xe, par, D, Dx, Dxx, Dxxx)
    return D, Dx, Dxx, Dxxx


def kernel_inertia(xe, ve, ae, ipar, gravity=GRAVITY):
    M, r, C, K = np.zeros((N, N)), np.zeros(N), np.zeros((N, N)), np.zeros((N, N))
    spatial_beam.inertia(xe, ve, ae, ipar, gravity, M, r, C, K)
    return M, r, C, K


def reference(seed=0, l0=0.8):
    """A beam of length l0 along a random direction, nodes with random body frames:
    (xe (14,) reference coordinates, par (19,), section axes (3,3) rows in global)."""
    rng = np.random.default_rng(seed)
    x_p = rng.standard_normal(3)
    axes = Rotation.random(random_state=seed + 1).as_matrix().T
    x_q = x_p + l0 * axes[0]
    lam_p = quat(Rotation.random(random_state=seed + 2).as_matrix())
    lam_q = quat(Rotation.random(random_state=seed + 3).as_matrix())
    par = beam_parameters(x_p, lam_p, x_q, lam_q, axes[1] + 0.3 * axes[0])
    return np.r_[x_p, lam_p, x_q, lam_q], par, axes


def deformed(seed=0, amp=0.05):
    xe, par, _ = reference(seed)
    return xe + amp * np.random.default_rng(seed + 10).standard_normal(N), par


def ipar_of(par, lumped):
    return np.r_[par, 2.5, section_second_moments(0.05, 0.02, 0.03), float(lumped)]


def _fd(fun, x, h=1e-5):
    """Central differences of fun (array-valued) w.r.t. x, derivative index last."""
    return np.stack([(np.asarray(fun(x + h * e)) - np.asarray(fun(x - h * e))) / (2 * h) for e in np.eye(x.size)],
                    axis=-1)


def _close(got, want, rel):
    np.testing.assert_allclose(got, want, rtol=0, atol=rel * max(1.0, np.abs(want).max()))


# ----------------------------------------------------------------------------- deformation
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_deformation_matches_twin(seed):
    xe, par = deformed(seed, amp=0.1)
    for got, want in zip(kernel_deformation(xe, par), beam_deformation_twin(xe, par)):
        _close(got, want, 1e-13)


def test_deformation_derivatives_by_finite_differences():
    xe, par = deformed(3)
    D, Dx, Dxx, Dxxx = kernel_deformation(xe, par)
    order = lambda i: (lambda x: kernel_deformation(x, par)[i])
    np.testing.assert_allclose(_fd(order(0), xe, 1e-6), Dx, atol=1e-8)
    np.testing.assert_allclose(_fd(order(1), xe, 1e-6), Dxx, atol=1e-7)
    np.testing.assert_allclose(_fd(order(2), xe, 1e-5), Dxxx, atol=1e-6)


def test_rigid_motions_give_zero_deformation():
    xe, par, _ = reference(4)
    assert np.abs(kernel_deformation(xe, par)[0]).max() < 1e-14
    for seed in range(3):
        R = Rotation.random(random_state=20 + seed).as_matrix()
        d = RNG.standard_normal(3)
        moved = np.r_[R @ xe[0:3] + d, quat(R @ rot(xe[3:7])), R @ xe[7:10] + d,
                      quat(R @ rot(xe[10:14]))]
        assert np.abs(kernel_deformation(moved, par)[0]).max() < 1e-14


def test_modes_do_not_depend_on_the_euler_parameters_norm():
    xe, par = deformed(5)
    D, Dx = kernel_deformation(xe, par)[:2]
    scaled = xe.copy()
    scaled[3:7] *= 1.3
    scaled[10:14] *= 0.7
    np.testing.assert_allclose(kernel_deformation(scaled, par)[0], D, atol=1e-14)
    np.testing.assert_allclose(Dx[:, 3:7] @ xe[3:7], 0.0, atol=1e-14)
    np.testing.assert_allclose(Dx[:, 10:14] @ xe[10:14], 0.0, atol=1e-14)


def _planar_lift(z):
    """Spatial coordinates (14,) of a planar beam's (x, y, phi) per node, and the lift's
    first to third derivatives w.r.t. z (6,)."""
    x = np.zeros(N)
    J1, J2, J3 = np.zeros((N, 6)), np.zeros((N, 6, 6)), np.zeros((N, 6, 6, 6))
    for node in range(2):
        o, p = 7 * node, 3 * node
        f = z[p + 2] / 2
        x[o:o + 7] = [z[p], z[p + 1], 0.0, np.cos(f), 0.0, 0.0, np.sin(f)]
        J1[o, p] = J1[o + 1, p + 1] = 1.0
        for i, d in enumerate(((-np.sin(f), np.cos(f)), (-np.cos(f), -np.sin(f)), (np.sin(f), -np.cos(f)))):
            J = (J1, J2, J3)[i]
            idx = (p + 2,) * (i + 1)
            J[(o + 3,) + idx] = d[0] / 2 ** (i + 1)
            J[(o + 6,) + idx] = d[1] / 2 ** (i + 1)
    return x, J1, J2, J3


@pytest.mark.parametrize("seed", [0, 1])
def test_planar_motion_reproduces_the_planar_beam(seed):
    """In the x-y plane the spatial beam's (elongation, bending_z_p, bending_z_q) and their
    first to third derivatives, composed with the planar-to-spatial lift, equal the planar
    beam's (complex-number derivatives) to 1e-12."""
    rng = np.random.default_rng(seed)
    z = np.array([0.1, -0.2, 0.3, 0.45, 0.05, 0.2]) + 0.05 * rng.standard_normal(6)
    l0, cp, cq = 0.42, 0.05, -0.1
    axes_in_body = lambda c: np.array([[np.cos(c), np.sin(c), 0], [-np.sin(c), np.cos(c), 0], [0, 0, 1.0]])
    par = np.r_[l0, axes_in_body(cp).ravel(), axes_in_body(cq).ravel()]
    x, J1, J2, J3 = _planar_lift(z)
    D, Dx, Dxx, Dxxx = kernel_deformation(x, par)
    P1 = Dx @ J1
    P2 = np.einsum("kab,ai,bj->kij", Dxx, J1, J1) + np.einsum("ka,aij->kij", Dx, J2)
    t = np.einsum("kab,aij,bl->kijl", Dxx, J2, J1)
    P3 = (np.einsum("kabc,ai,bj,cl->kijl", Dxxx, J1, J1, J1) + t + t.transpose(0, 1, 3, 2)
          + t.transpose(0, 3, 2, 1) + np.einsum("ka,aijl->kijl", Dx, J3))
    d, dx, dxx, dxxx = np.zeros(3), np.zeros((3, 6)), np.zeros((3, 6, 6)), np.zeros((3, 6, 6, 6))
    planar_beam.deformation(z, np.array([l0, cp, cq]), d, dx, dxx, dxxx)
    sel = [0, 2, 3]
    for got, want in ((D[sel], d), (P1[sel], dx), (P2[sel], dxx), (P3[sel], dxxx)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    # the out-of-plane modes stay zero to third order along the plane
    for got in (D[[1, 4, 5]], P1[[1, 4, 5]], P2[[1, 4, 5]], P3[[1, 4, 5]]):
        assert np.abs(got).max() < 1e-12


def _bent_beam(amp, chord=1.0):
    """A cubic Hermite centre line along x with end rotations ~amp about y and z, sections
    carried along it by the rotation-minimizing (zero torsional curvature) frame. Returns
    (xe, par, arc length, end rotations (a_p, a_q, b_p, b_q))."""
    a = amp * np.array([1.0, -0.6, 0.8, 0.5])   # slopes: dy/dx at p, q; dz/dx at p, q
    def r1(s):   # tangent dr/ds, s in [0, 1]
        gp, gq = 1 - 4 * s + 3 * s**2, -2 * s + 3 * s**2
        return chord * np.array([1.0, a[0] * gp + a[1] * gq, a[2] * gp + a[3] * gq])
    def r2(s):
        return chord * np.array([0.0, a[0] * (6 * s - 4) + a[1] * (6 * s - 2), a[2] * (6 * s - 4) + a[3] * (6 * s - 2)])
    def rhs(s, y):
        d1, d2 = r1(s), r2(s)
        w = np.cross(d1, d2) / (d1 @ d1)   # angular rate of the unit tangent
        e2, e3 = y[:3], y[3:]
        return np.r_[np.cross(w, e2), np.cross(w, e3)]
    t0 = r1(0.0) / np.linalg.norm(r1(0.0))
    e2 = np.array([0.0, 1.0, 0.0]) - t0[1] * t0
    e2 /= np.linalg.norm(e2)
    sol = solve_ivp(rhs, (0, 1), np.r_[e2, np.cross(t0, e2)], rtol=1e-12, atol=1e-14)
    frames = []
    for s, y in ((0.0, sol.y[:, 0]), (1.0, sol.y[:, -1])):
        t = r1(s) / np.linalg.norm(r1(s))
        frames.append(np.column_stack([t, y[:3], y[3:]]))
    gs, gw = np.polynomial.legendre.leggauss(40)   # smooth integrand: exact to round-off
    arc = 0.5 * sum(w * np.linalg.norm(r1(0.5 * (s + 1))) for s, w in zip(gs, gw))
    x_q = np.array([chord, 0.0, 0.0])
    xe = np.r_[np.zeros(3), quat(frames[0]), x_q, quat(frames[1])]
    par = np.r_[arc, np.eye(3).ravel(), np.eye(3).ravel()]
    return xe, par, arc


def test_second_order_terms_follow_the_hermite_centre_line():
    """For an inextensible Hermite centre line with torsion-free sections, elongation and
    torsion vanish to the order the second-order terms promise: the elongation error is
    O(amp^4) and the torsion at least O(amp^3), while their second-order terms alone are O(amp^2)."""
    results = []
    for amp in (0.02, 0.01):
        xe, par, arc = _bent_beam(amp)
        D = kernel_deformation(xe, par)[0]
        a_p, a_q, b_p, b_q = D[2:]
        correction = b_p * a_q - b_q * a_p
        bow = D[0] - (1.0 - arc)
        results.append((abs(D[0]), abs(D[1]), abs(correction), abs(bow)))
    (e1, t1, c1, w1), (e2, t2, c2, w2) = results
    assert t1 < 0.05 * c1 and e1 < 0.05 * w1
    assert t1 / t2 > 7.0 and e1 / e2 > 14.0   # third and fourth order
    assert c1 / c2 == pytest.approx(4.0, rel=0.05) and w1 / w2 == pytest.approx(4.0, rel=0.05)


# ----------------------------------------------------------------------------- inertia
@pytest.mark.parametrize("lumped", [True, False])
def test_inertia_matches_twin(lumped):
    xe, par = deformed(6, amp=0.1)
    ipar = ipar_of(par, lumped)
    ve, ae = RNG.standard_normal(N), RNG.standard_normal(N)
    for got, want in zip(kernel_inertia(xe, ve, ae, ipar), beam_inertia_twin(xe, ve, ae, ipar, GRAVITY)):
        _close(got, want, 1e-13)


@pytest.mark.parametrize("lumped", [True, False])
def test_inertia_derivatives_by_finite_differences(lumped):
    xe, par = deformed(7, amp=0.1)
    ipar = ipar_of(par, lumped)
    ve, ae = RNG.standard_normal(N), RNG.standard_normal(N)
    M, r, C, K = kernel_inertia(xe, ve, ae, ipar)
    np.testing.assert_allclose(M, M.T, atol=1e-15)
    res = lambda x, v, a: kernel_inertia(x, v, a, ipar)[1]
    np.testing.assert_allclose(_fd(lambda a: res(xe, ve, a), ae, 1e-6), M, atol=1e-8)
    np.testing.assert_allclose(_fd(lambda v: res(xe, v, ae), ve, 1e-6), C, atol=1e-8)
    np.testing.assert_allclose(_fd(lambda x: res(x, ve, ae), xe, 1e-6), K, atol=1e-8)


@pytest.mark.parametrize("lumped", [True, False])
def test_rigid_motion_energy_and_weight(lumped):
    """For a rigid motion the kinetic energy 1/2 v^T M v is the rigid body's (rod plus
    section rotary inertia) and the gravity force is the weight at the centre."""
    xe, par, axes = reference(8)
    rhoA, Jsec = 2.5, np.array([0.05, 0.02, 0.03])
    ipar = np.r_[par, rhoA, section_second_moments(*Jsec), float(lumped)]
    l0 = par[0]
    v0, w = RNG.standard_normal(3), RNG.standard_normal(3)
    ve = np.zeros(N)
    for node in range(2):
        o = 7 * node
        lam = xe[o + 3:o + 7]
        ve[o:o + 3] = v0 + np.cross(w, xe[o:o + 3] - xe[0:3])
        ve[o + 3:o + 7] = 0.5 * np.r_[-w @ lam[1:], lam[0] * w + np.cross(w, lam[1:])]
    M, r = kernel_inertia(xe, ve, np.zeros(N), ipar, np.zeros(3))[:2]
    m = rhoA * l0
    vc = v0 + np.cross(w, 0.5 * (xe[7:10] - xe[0:3]))
    n = axes[0]
    J = m * l0**2 / 12 * (np.eye(3) - np.outer(n, n)) + l0 * axes.T @ np.diag(Jsec) @ axes
    assert 0.5 * ve @ M @ ve == pytest.approx(0.5 * m * vc @ vc + 0.5 * w @ J @ w, rel=1e-13)
    # gravity: the generalized force on a translation is the weight
    f = -kernel_inertia(xe, np.zeros(N), np.zeros(N), ipar)[1]
    np.testing.assert_allclose(f[0:3] + f[7:10], m * GRAVITY, rtol=1e-13)


def test_interpolation_integrals():
    hm, hw = _gauss(HERMITE)
    np.testing.assert_allclose(spatial_beam.HERMITE_MASS, hm, atol=1e-15)
    np.testing.assert_allclose(spatial_beam.HERMITE_WEIGHTS, hw, atol=1e-15)
    np.testing.assert_allclose(spatial_beam.SLOPE_MASS, _gauss(SLOPES)[0], atol=1e-15)


# ----------------------------------------------------------------------------- model data
def test_spatial_beam_data_and_errors():
    beam = SpatialBeam("b", ("p", "q"), ("Rp", "Rq"), ("flexible",) * 6,
                       BeamSection(EA=3.0, GJ=2.0, EI_y=5.0, EI_z=7.0), kelvin_voigt=0.01)
    S = beam.stiffness_matrix(2.0)
    np.testing.assert_allclose(np.diag(S), [1.5, 1.0, 14.0, 14.0, 10.0, 10.0])
    assert S[2, 3] == 7.0 and S[4, 5] == 5.0 and S[0, 1] == 0.0
    np.testing.assert_allclose(beam.damping_matrix(2.0), 0.01 * S)
    per_mode = SpatialBeam("b", ("p", "q"), ("Rp", "Rq"), ("flexible",) * 6, beam.section,
                           kelvin_voigt=(0.0, 0.02, 0.01, 0.01, 0.03, 0.03))
    Sd = per_mode.damping_matrix(2.0)
    np.testing.assert_allclose(Sd, Sd.T)
    np.testing.assert_allclose(np.diag(Sd), [0.0, 0.02, 0.14, 0.14, 0.3, 0.3])
    with pytest.raises(InputError, match="bending pair"):
        SpatialBeam("b", ("p", "q"), ("Rp", "Rq"), ("flexible",) * 6, beam.section,
                    kelvin_voigt=(0.0, 0.02, 0.01, 0.02, 0.03, 0.03))
    with pytest.raises(InputError, match="one per mode"):
        SpatialBeam("b", ("p", "q"), ("Rp", "Rq"), ("flexible",) * 6, beam.section, kelvin_voigt=(0.1, 0.2))
    assert beam.coordinates() == ["p.x", "p.y", "p.z", "Rp.l0", "Rp.l1", "Rp.l2", "Rp.l3",
                                  "q.x", "q.y", "q.z", "Rq.l0", "Rq.l1", "Rq.l2", "Rq.l3"]
    ident = np.array([1.0, 0, 0, 0])
    with pytest.raises(InputError, match="zero length"):
        beam_parameters(np.zeros(3), ident, np.zeros(3), ident, (0, 1, 0))
    with pytest.raises(InputError, match="along the beam"):
        beam_parameters(np.zeros(3), ident, np.ones(3), ident, (2, 2, 2))
    with pytest.raises(InputError, match="unit norm"):
        beam_parameters(np.zeros(3), 2 * ident, np.ones(3), ident, (0, 1, 0))
    with pytest.raises(InputError, match="EA"):
        BeamSection(EA=-1.0)
    with pytest.raises(InputError, match="BeamSection"):
        SpatialBeam("b", ("p", "q"), ("Rp", "Rq"), ("flexible",) * 6, 3.0)
    with pytest.raises(InputError, match="beam 'b': y_axis is zero"):
        beam.parameters(np.r_[0, 0, 0, ident, 0, 1, 0, ident])   # the default y axis along the beam
    circ = BeamSection.solid_circular(0.03, 210e9, 0.3, 7850.0)
    assert circ.GJ == pytest.approx(210e9 / 2.6 * np.pi * 0.03**4 / 2)
    assert circ.polar_inertia == pytest.approx(circ.rotary_inertia_y + circ.rotary_inertia_z)


def _qmul(a, b):
    """Quaternion product (scalar first)."""
    return np.r_[a[0] * b[0] - a[1:] @ b[1:], a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:])]


def test_lumped_rotary_inertia_obeys_euler_equations():
    """With rhoA = 0 and lumped rotary inertia each node is a rigid body of inertia
    l0/2 J (body frame J = A^T diag(J_sec) A): for a motion with body angular velocity w
    and acceleration w', the generalized force on lam, applied to any admissible
    variation (lam . d lam = 0, body virtual rotation d theta = 2 lam^* d lam), is the
    virtual work of Euler's torque J w' + w x J w."""
    xe, par, _ = reference(9)
    Jsec = np.array([0.05, 0.02, 0.03])
    ipar = np.r_[par, 0.0, section_second_moments(*Jsec), 1.0]
    l0 = par[0]
    ve, ae = np.zeros(N), np.zeros(N)
    omegas = []
    for node in range(2):
        o = 7 * node + 3
        lam = xe[o:o + 4]
        w, wd = RNG.standard_normal(3), RNG.standard_normal(3)
        lam_d = 0.5 * _qmul(lam, np.r_[0.0, w])
        ve[o:o + 4] = lam_d
        ae[o:o + 4] = 0.5 * _qmul(lam_d, np.r_[0.0, w]) + 0.5 * _qmul(lam, np.r_[0.0, wd])
        omegas.append((w, wd))
    r = kernel_inertia(xe, ve, ae, ipar, np.zeros(3))[1]
    for node in range(2):
        o = 7 * node + 3
        lam = xe[o:o + 4]
        A = par[1 + 9 * node:10 + 9 * node].reshape(3, 3)
        J = 0.5 * l0 * A.T @ np.diag(Jsec) @ A
        w, wd = omegas[node]
        torque = J @ wd + np.cross(w, J @ w)
        for _ in range(3):
            d = RNG.standard_normal(4)
            d -= (d @ lam) * lam
            theta = 2 * _qmul(np.r_[lam[0], -lam[1:]], d)
            assert abs(theta[0]) < 1e-14
            assert d @ r[o:o + 4] == pytest.approx(theta[1:] @ torque, rel=1e-12)
