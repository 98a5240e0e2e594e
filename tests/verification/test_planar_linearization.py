"""Linearized equations (eq. 5, 7, 9, 10, 11-12) against finite differences of the
non-linear reduced equations (4), and the omega-split against direct linearization."""

import dataclasses

import numpy as np
import pytest

from periodyn.examples.slider_crank_rod import slider_crank, slider_crank_model
from periodyn.model.linearization import linearize, omega_split, reduced_residual
from periodyn.model import IndependentElement


@pytest.fixture(scope="module")
def model():
    """Slider-crank with damping and the sections' rotary inertia, so every term counts."""
    return slider_crank_model(kelvin_voigt=4.8e-5, rotary_inertia_per_length=2e-5)


@pytest.mark.parametrize("sample", [3, 10])
def test_linearized_matrices_are_derivatives_of_the_nonlinear_equations(model, sample):
    omega, p = 220.0, 16
    lin = linearize(model, omega, p)
    theta = 2 * np.pi * sample / p
    zero = np.zeros(4)
    R = lambda q, qd, qdd: reduced_residual(model, theta, q, qd, qdd, omega)
    np.testing.assert_allclose(R(zero, zero, zero), lin.additional_force[sample], rtol=1e-10,
                               atol=1e-12 * np.abs(lin.additional_force).max())
    h = 1e-6
    M, C, K = (np.empty((4, 4)) for _ in range(3))
    for i in range(4):
        e = np.zeros(4)
        e[i] = h
        K[:, i] = (R(e, zero, zero) - R(-e, zero, zero)) / (2 * h)
        C[:, i] = (R(zero, e * 1e3, zero) - R(zero, -e * 1e3, zero)) / (2e3 * h)
        M[:, i] = (R(zero, zero, e * 1e3) - R(zero, zero, -e * 1e3)) / (2e3 * h)
    np.testing.assert_allclose(M, lin.mass[sample], rtol=1e-7, atol=1e-9 * np.abs(lin.mass).max())
    np.testing.assert_allclose(C, lin.damping[sample], rtol=1e-6, atol=1e-7 * np.abs(lin.damping).max())
    np.testing.assert_allclose(K, lin.stiffness[sample], rtol=1e-6, atol=1e-6 * np.abs(lin.stiffness).max())


def test_mass_matrix_is_symmetric_positive_definite(model):
    lin = linearize(model, 150.0, 16)
    np.testing.assert_allclose(lin.mass, np.swapaxes(lin.mass, 1, 2), atol=1e-16)
    assert np.all(np.linalg.eigvalsh(lin.mass) > 0)


def _with_independent(model, element):
    idx = np.array([model.coordinate_names.index(c) for c in element.coordinates])
    return dataclasses.replace(model, independent=((element, idx),))


BEARING = IndependentElement("bearing", ("R1.x", "R1.y"),
                             stiffness=(np.diag([1e3, 2e3]), np.array([[0, 5.0], [-5.0, 0]])),
                             damping=(np.diag([0.5, 0.7]), np.array([[0, 1e-3], [-1e-3, 0]])),
                             mass=np.diag([0.01, 0.01]), force=np.array([0.0, -0.2]))


def test_omega_split_equals_direct_linearization_at_several_speeds():
    base = slider_crank_model(kelvin_voigt=4.8e-5)
    model = _with_independent(base, BEARING)
    split = omega_split(model, 24)
    for omega in (0.7, 150.0, 233.3, 300.0):
        direct = linearize(model, omega, 24)
        system = split.at(omega)
        for got, want in ((system.mass, direct.mass), (system.damping, direct.damping),
                          (system.stiffness, direct.stiffness), (system.force, direct.force)):
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max() * max(1, omega / 100) ** 2)
    # the independent element changed the equations
    plain = linearize(base, 150.0, 24)
    assert np.abs(plain.stiffness - linearize(model, 150.0, 24).stiffness).max() > 1.0


def test_independent_element_adds_its_matrices_through_the_transfer_function():
    """For the pendulum angle (Fd = 1, Fdv = Fda = 0) a rotational spring-damper-inertia
    adds exactly (k, c, J), and its force adds to the right-hand side."""
    from periodyn.examples.elliptic_pendulum import elliptic_pendulum_model
    base = elliptic_pendulum_model()
    el = IndependentElement("spring", ("pendulum",), stiffness=(np.array([[3.0]]),), damping=(np.array([[0.2]]),),
                            mass=np.array([[0.5]]), force=np.array([0.7]))
    model = _with_independent(base, el)
    a, b = linearize(base, 2.0, 8), linearize(model, 2.0, 8)
    np.testing.assert_allclose(b.mass - a.mass, 0.5, atol=1e-14)
    np.testing.assert_allclose(b.damping - a.damping, 0.2, atol=1e-14)
    np.testing.assert_allclose(b.stiffness - a.stiffness, 3.0, atol=1e-13)
    np.testing.assert_allclose(b.force - a.force, 0.7, atol=1e-14)


def test_split_output_maps_give_the_linearized_midpoint_deflection():
    """G q^d equals the change of the (non-linear) midpoint deflection for small q^d."""
    from periodyn.model.kinematics import configuration
    from periodyn.kernels.mechanism.outputs import midpoint_deflection
    model = slider_crank_model()
    split = slider_crank(0.02, 16)
    qd = 1e-6 * np.array([1.0, -2.0, 0.5, 3.0])
    idx = model.outputs[0].dofs
    for j in (0, 5):
        theta = 2 * np.pi * j / 16
        y = midpoint_deflection(configuration(model, theta, qd)[idx], 0.3, np.empty(6))
        assert y == pytest.approx(split.output_maps[j, 0] @ qd, rel=1e-5)


@pytest.mark.parametrize("driven", [False, True])
def test_split_kernel_equals_reduced_sample_at_each_speed(driven):
    """kernels.split (transfer function differentiated once, element arrays split into powers,
    one product for all powers) against reduced_sample evaluated at each speed, at nominal
    and deformed configurations of a slider-crank with 6 rod elements; driven: with an
    input acceleration s^2 g'' besides the rate s g' (a crank speed that varies with the
    angle) and nodal loads that enter only the speed-independent power."""
    from periodyn.kernels.mechanism.assembly import reduced_sample
    from periodyn.kernels.mechanism.split import split_sample
    from periodyn.model.kinematics import configuration

    model = slider_crank_model(kelvin_voigt=4.8e-5, rod_elements=6)
    arr, n, nd = model.arrays, model.n_coordinates, model.n_dynamic
    rng = np.random.default_rng(7)
    qdot1 = np.concatenate([model.input_rates * (1.3 if driven else 1.0), np.zeros(nd)])
    qddot1 = np.concatenate([[0.4 if driven else 0.0], np.zeros(nd)])
    load = rng.standard_normal(n) if driven else np.zeros(n)
    for theta, qd in ((0.4, np.zeros(nd)), (2.1, 1e-3 * rng.standard_normal(nd))):
        x = configuration(model, theta, qd)
        M, C, K, f = np.empty((nd, nd)), np.empty((2, nd, nd)), np.empty((3, nd, nd)), np.empty((3, nd))
        F1 = [np.empty((n, nd)) for _ in range(3)]
        split_sample(arr, x, qdot1, qddot1, load, 200.0, M, C, K, f, *F1)
        for s in (-90.0, 37.0, 250.0):
            Mb, Cb, Kb, fd = np.empty((nd, nd)), np.empty((nd, nd)), np.empty((nd, nd)), np.empty(nd)
            F = [np.empty((n, nd)) for _ in range(3)]
            reduced_sample(arr, x, s * qdot1, s**2 * qddot1, load, Mb, Cb, Kb, fd, *F)
            for got, want in ((M, Mb), (C[0] + s * C[1], Cb), (K[0] + s * K[1] + s**2 * K[2], Kb),
                              (f[0] + s * f[1] + s**2 * f[2], fd), (F1[0], F[0]), (s * F1[1], F[1]),
                              (s**2 * F1[2], F[2])):
                np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max())
