"""Planar multibody kernels against plain-NumPy twins (~1e-13) and finite differences.

The twins live in tests/twins/planar.py (also used by benchmarks/bench_linearize.py).
"""

import numpy as np
import pytest
from scipy.integrate import trapezoid

from periodyn.examples.slider_crank_rod import slider_crank_model
from periodyn.kernels.elements import elastic, planar_beam, planar_hinge, planar_truss
from periodyn.kernels.mechanism import outputs
from periodyn.model.kinematics import nominal_configurations
from periodyn.model import PlanarBeam
from tests.twins.planar import (beam_deformation_twin, beam_inertia_twin, elastic_twin, kernel_sample,
                                 midpoint_twin, motion_twin, truss_deformation_twin)

RNG = np.random.default_rng(7)
HERMITE_MASS = np.array([[13 / 35, 9 / 70, 11 / 210, -13 / 420], [9 / 70, 13 / 35, 13 / 420, -11 / 210],
                         [11 / 210, 13 / 420, 1 / 105, -1 / 140], [-13 / 420, -11 / 210, -1 / 140, 1 / 105]])
HERMITE_WEIGHTS = np.array([0.5, 0.5, 1 / 12, -1 / 12])


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
    arc = 0.5 * trapezoid(np.sqrt(1 + slope**2), s)
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

    ipar = planar_beam.pack_inertia(par, mass, weights, rotary)

    def kernel(x, v, a):
        out = [np.zeros((6, 6)), np.zeros(6), np.zeros((6, 6)), np.zeros((6, 6))]
        planar_beam.inertia(x, v, a, ipar, gravity, *out)
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
    planar_beam.inertia(np.array([0, 0, 0, l0, 0, 0.0]), np.zeros(6), np.zeros(6),
                        beam.inertia_parameters(np.array([l0, 0, 0.0])), np.zeros(2), M, np.zeros(6),
                        np.zeros((6, 6)), np.zeros((6, 6)))
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
    ipar = np.concatenate([mass.ravel(), [0.25, 0.25]])
    planar_truss.inertia(xe, np.zeros(4), ae, ipar, np.array([0, -9.81]), M, r, np.zeros((4, 4)), np.zeros((4, 4)))
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
    s0 = np.array([2.0, -0.3, 0.1])  # constant stresses (an axial preload, end moments)

    def kernel(x, v):
        D, Dx, Dxx, _ = _kernel_deformation(planar_beam.deformation, x, par, 3, 6)
        r, C, K = np.zeros(6), np.zeros((6, 6)), np.zeros((6, 6))
        elastic.add_elastic(3, 6, D, Dx, Dxx, v, S, Sd, s0, r, C, K)
        return r, C, K, (D, Dx, Dxx)

    r, C, K, (D, Dx, Dxx) = kernel(xe, ve)
    for g, t in zip((r, C, K), elastic_twin(D, Dx, Dxx, ve, S, Sd, s0)):
        np.testing.assert_allclose(g, t, atol=1e-13 * max(1, np.abs(t).max()))
    np.testing.assert_allclose(_fd(lambda v: kernel(xe, v)[0], ve, 1e-4), C, atol=1e-9)
    np.testing.assert_allclose(_fd(lambda x: kernel(x, ve)[0], xe, 1e-7), K, rtol=1e-6, atol=1e-5)


def test_midpoint_deflection_matches_twin_and_gradient():
    xe = np.array([0.1, 0.0, 0.3, 0.02, 0.5, 0.01])
    grad = np.empty(6)
    y = outputs.midpoint_deflection(xe, 0.3, grad)
    assert y == pytest.approx(midpoint_twin(xe, 0.3), abs=1e-15)
    np.testing.assert_allclose(_fd(lambda x: np.array(midpoint_twin(x, 0.3)), xe, 1e-6), grad, atol=1e-8)


def test_per_sample_linearization_matches_numpy_twin():
    model = slider_crank_model(kelvin_voigt=5e-5, rotary_inertia_per_length=1e-4)
    X = nominal_configurations(model, 8)
    qdot = np.array([200.0, 0.3, -0.2, 0.1, 0.4])
    qddot = np.array([50.0, 1.0, 2.0, -1.0, 0.5])
    for x in X[[1, 3, 6]]:
        for g, t in zip(kernel_sample(model, x, qdot, qddot), motion_twin(model, x, qdot, qddot)):
            np.testing.assert_allclose(g, t, rtol=0, atol=1e-13 * np.abs(t).max())


def test_adjoint_curvature_term_equals_the_direct_second_derivative_form():
    """reduced_sample forms sum_k r_k F_{q^d q^d}[k] as -mu . Phi_xx[F_d, F_d] with the
    constraint forces mu = J^-T r; the direct form contracts r with all n_d^2 second
    derivatives of the transfer function (transfer.motion's Fdd)."""
    from periodyn.kernels.mechanism import assembly, transfer

    model = slider_crank_model(kelvin_voigt=5e-5, rod_elements=6, rotary_inertia_per_length=1e-4)
    n, nd = model.n_coordinates, model.n_dynamic
    X = nominal_configurations(model, 8)
    rng = np.random.default_rng(3)
    qdot = np.concatenate([[180.0], 0.3 * rng.standard_normal(nd)])
    qddot = np.concatenate([[40.0], rng.standard_normal(nd)])
    for x in X[[0, 2, 5]]:
        Mb, Cb, Kb, fd = kernel_sample(model, x, qdot, qddot)
        v, a, Fd, Fdv, Fda = np.empty(n), np.empty(n), np.empty((n, nd)), np.empty((n, nd)), np.empty((n, nd))
        Fdd = np.empty((n, nd, nd))
        D, Dx, Dxx = transfer.motion(model.arrays, x, qdot, qddot, v, a, Fd, Fdv, Fdd, Fda)
        M, r, C, K = np.empty((n, n)), np.empty(n), np.empty((n, n)), np.empty((n, n))
        assembly.nodal_arrays(model.arrays, x, v, a, D, Dx, Dxx, M, r, C, K)
        direct = Fd.T @ K @ Fd + (M @ Fd).T @ Fda + Fd.T @ C @ Fdv + np.einsum("k,kij->ij", r, Fdd)
        assert np.abs(np.einsum("k,kij->ij", r, Fdd)).max() > 1e-3 * np.abs(direct).max()  # the term matters
        np.testing.assert_allclose(Kb, direct, rtol=0, atol=1e-12 * np.abs(direct).max())
