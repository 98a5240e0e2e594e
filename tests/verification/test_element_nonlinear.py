"""The full non-linear equations (4) of element models (periodyn.nonlinear.elements):
Jacobians against finite differences, the accelerations against the residual form, the
residual form at the rigid motion against the linearized equations, the element-built
pendulum against the hand-written eq. (28), and shooting against harmonic balance and
long direct integration."""

import numpy as np
import pytest

import periodyn
from periodyn.errors import ConvergenceError, InputError
from periodyn.examples.elliptic_pendulum import elliptic_pendulum_model, pendulum_from_elements
from periodyn.examples.pendulum_equation import pendulum_nonlinear
from periodyn.examples.slider_crank_rod import slider_crank_model
from periodyn.model.linearization import linearize
from periodyn.nonlinear.elements import element_dae, element_outputs, reduced_equations
from periodyn.numerics.integration import integrate
from periodyn.dae import rheo_linear_dae
from periodyn.numerics.stiff import integrate_stiff

OMEGA = 220.0  # rad/s


@pytest.fixture(scope="module")
def crank():
    """Slider-crank with damping and the sections' rotary inertia, so every term counts."""
    return slider_crank_model(kelvin_voigt=4.8e-5, rotary_inertia_per_length=2e-5)


@pytest.fixture(scope="module")
def states():
    rng = np.random.default_rng(1)
    return rng.normal(size=(3, 4)) * 2e-2, rng.normal(size=(3, 4)) * 3.0, np.array([0.002, 0.011, 0.023])


def test_force_jacobians_match_finite_differences(crank, states):
    dae = element_dae(crank)
    q, qd, t = states
    Gq, Gv = dae.force_jacobians(q, qd, t, OMEGA, {})
    h = 1e-7
    for i in range(4):
        e = np.zeros(4)
        e[i] = h
        fq = (dae.force(q + e, qd, t, OMEGA, {}) - dae.force(q - e, qd, t, OMEGA, {})) / (2 * h)
        fv = (dae.force(q, qd + 1e2 * e, t, OMEGA, {}) - dae.force(q, qd - 1e2 * e, t, OMEGA, {})) / (2e2 * h)
        np.testing.assert_allclose(fq, Gq[:, :, i], rtol=0, atol=1e-7 * np.abs(Gq).max())
        np.testing.assert_allclose(fv, Gv[:, :, i], rtol=0, atol=1e-6 * np.abs(Gv).max())


def test_accelerations_solve_the_residual_form(crank, states):
    """The lean force path (kernels.nonlinear) against reduced_sample: R(q, q', g) = 0,
    and the Jacobians are -M̄⁻¹ K̄, -M̄⁻¹ C̄ at the actual accelerations."""
    dae = element_dae(crank)
    q, qd, t = states
    acc = dae.force(q, qd, t, OMEGA, {})
    Gq, Gv = dae.force_jacobians(q, qd, t, OMEGA, {})
    R, Mb, Cb, Kb = reduced_equations(crank, OMEGA, t, q, qd, acc)
    scale = np.abs(np.einsum("kij,kj->ki", Mb, acc)).max()
    np.testing.assert_allclose(R, 0.0, atol=1e-12 * scale)
    np.testing.assert_allclose(np.einsum("kij,kjl->kil", Mb, Gq), -Kb, rtol=0, atol=1e-10 * np.abs(Kb).max())
    np.testing.assert_allclose(np.einsum("kij,kjl->kil", Mb, Gv), -Cb, rtol=0, atol=1e-10 * np.abs(Cb).max())


def test_linearizing_about_the_rigid_motion_gives_the_rheo_linear_system(crank):
    p = 16
    lin = linearize(crank, OMEGA, p)
    t = np.arange(p) * 2 * np.pi / (p * OMEGA)
    zero = np.zeros((p, 4))
    R, Mb, Cb, Kb = reduced_equations(crank, OMEGA, t, zero, zero, zero)
    for got, want in ((R, lin.additional_force), (Mb, lin.mass), (Cb, lin.damping), (Kb, lin.stiffness)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * np.abs(want).max())
    # the ODE's accelerations and velocity Jacobian at the rigid motion are those of the rheo-linear system
    dae = element_dae(crank)
    acc = dae.force(zero, zero, t, OMEGA, {})
    np.testing.assert_allclose(np.einsum("pij,pj->pi", lin.mass, acc), lin.force, rtol=0,
                               atol=1e-10 * np.abs(lin.force).max())
    _, Gv = dae.force_jacobians(zero, zero, t, OMEGA, {})
    np.testing.assert_allclose(lin.mass @ Gv, -lin.damping, rtol=0, atol=1e-10 * np.abs(lin.damping).max())


def test_states_beyond_the_mechanisms_reach_get_nan_and_leave_the_others_intact(crank):
    """A trial state far outside the reach of the kinematics (end rotations of -3 rad)
    gets NaN accelerations (step control rejects it); its neighbours in the batch and
    the next calls are unaffected."""
    dae = element_dae(crank)
    q = np.array([[1e-3, 0, 0, 0], [-3.0, -3.0, -3.0, -3.0], [2e-3, 0, 0, 0]])
    t = np.array([0.001, 0.002, 0.003])
    acc = dae.force(q, np.zeros((3, 4)), t, OMEGA, {})
    assert np.isnan(acc[1]).all() and np.isfinite(acc[[0, 2]]).all()
    fresh = element_dae(crank).force(q[[0, 2]], np.zeros((2, 4)), t[[0, 2]], OMEGA, {})
    np.testing.assert_allclose(acc[[0, 2]], fresh, rtol=1e-12)
    np.testing.assert_allclose(dae.force(q[[0, 2, 0]], np.zeros((3, 4)), t[[0, 2, 0]], OMEGA, {})[:2], fresh, rtol=1e-12)


def test_element_pendulum_equals_equation_28():
    """The element-built elliptic pendulum (mass 1 kg, l = 1 m) is eq. (28) exactly."""
    dae = element_dae(elliptic_pendulum_model())
    ref = pendulum_nonlinear()
    rng = np.random.default_rng(2)
    q, qd, t = rng.uniform(-2.5, 2.5, (6, 1)), rng.normal(size=(6, 1)), rng.uniform(0, 5, 6)
    for omega in (0.7, 2.9):
        np.testing.assert_allclose(dae.force(q, qd, t, omega, {}), ref.force(q, qd, t, omega, ref.parameters),
                                   rtol=1e-11, atol=1e-11)


def test_models_without_a_nonlinear_meaning_are_refused():
    from periodyn.model import IndependentElement

    import dataclasses
    model = slider_crank_model()
    el = IndependentElement("spring", ("B.x",), stiffness=[np.eye(1)])
    with pytest.raises(InputError, match="independently modelled"):
        element_dae(dataclasses.replace(model, independent=((el, np.array([6])),)))


def test_shooting_the_linearized_pendulum_reproduces_harmonic_balance():
    """Eq. (29) of the element model, shot as an ODE, against harmonic balance."""
    omega = 0.4 * np.sqrt(9.81)
    system = pendulum_from_elements(samples=32).at(omega)
    hb = periodyn.periodic_solution(system, 12)
    shot = periodyn.shooting(rheo_linear_dae(system), omega, tol=1e-12, rtol=1e-12, samples=64)
    m = shot.m
    np.testing.assert_allclose(shot.harmonics[m - 12:m + 13], hb.harmonics, rtol=0, atol=1e-8)
    np.testing.assert_allclose(shot.amplitude(), hb.amplitude(), rtol=1e-8)


def test_nonlinear_pendulum_shooting_agrees_with_long_direct_integration():
    """Element model, non-linear, zeta = 0.05: shooting vs integration from rest over 60
    periods (transient decays by exp(-2 pi zeta omega0 60 / omega) < 1e-10)."""
    model = elliptic_pendulum_model(zeta=0.05)
    dae = element_dae(model)
    omega = 0.6 * np.sqrt(9.81)
    T = 2 * np.pi / omega
    shot = periodyn.shooting(dae, omega, tol=1e-11)
    th = integrate(dae, omega, (0.0, 60 * T), np.zeros(1), np.zeros(1), t_eval=60 * T + np.linspace(0, T, 9)[:1],
                   rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(th.q[-1], shot(0.0)[0], atol=1e-6)
    np.testing.assert_allclose(th.qd[-1], shot.velocity(0.0)[0], atol=1e-6)
    stiff = integrate_stiff(dae, omega, (0.0, T), shot(0.0)[0], shot.velocity(0.0)[0], t_eval=[T], rtol=1e-10,
                            atol=1e-12)
    np.testing.assert_allclose(stiff.q[-1], shot(T)[0], atol=1e-6)


def test_nonlinear_outputs_are_the_linear_outputs_to_first_order(crank):
    """Midpoint deflection of small deformations: y(x(q)) - y(x(q^r, 0)) = G q + O(q^2)."""
    from periodyn.model.linearization import rheo_linear

    p = 8
    G = rheo_linear(crank, OMEGA, p).output_maps[:, 0]  # (p, n_d)
    t = np.arange(p) * 2 * np.pi / (p * OMEGA)
    q = np.random.default_rng(3).normal(size=(p, 4))
    for eps in (1e-4, 1e-5):
        y = element_outputs(crank, OMEGA, t, eps * q)[:, 0]
        np.testing.assert_allclose(y / eps, np.einsum("pi,pi->p", G, q), rtol=0, atol=30 * eps * np.abs(G).max())


def test_shooting_that_does_not_converge_is_reported():
    dae = element_dae(elliptic_pendulum_model())
    with pytest.raises(ConvergenceError) as err:
        periodyn.shooting(dae, 0.95 * np.sqrt(9.81), max_iter=1, tol=1e-14)
    assert err.value.iterations >= 1 and np.isfinite(err.value.residual) and err.value.residual > 1e-14


def test_shooting_ihb_and_continuation_take_element_models_directly():
    """A builder Model and a CompiledModel are solved as their element_dae at the entry of
    shooting, ihb and continuation: the same orbits as from element_dae itself."""
    from periodyn.examples.elliptic_pendulum import elliptic_pendulum_builder

    omega = 0.6 * np.sqrt(9.81)
    builder = elliptic_pendulum_builder(zeta=0.05)
    dae = element_dae(builder.compile())
    ref_ihb = periodyn.ihb(dae, omega, 8, stability=None)
    ref_shot = periodyn.shooting(dae, omega, initial=ref_ihb, tol=1e-11)
    for model in (builder, builder.compile()):
        sol = periodyn.ihb(model, omega, 8, stability=None)
        np.testing.assert_allclose(sol.harmonics, ref_ihb.harmonics, rtol=0, atol=1e-12)
        shot = periodyn.shooting(model, omega, initial=sol, tol=1e-11)
        np.testing.assert_allclose(shot.harmonics, ref_shot.harmonics, rtol=0, atol=1e-10)
        assert shot.coordinate_names == dae.coordinate_names == ("pendulum",)
    branch = periodyn.continuation(builder.compile(), (omega, 1.05 * omega), 8, stability=None, max_points=20)
    assert branch.omega[-1] >= 1.05 * omega - 1e-9
    np.testing.assert_allclose(branch.solutions[0].harmonics, ref_ihb.harmonics, rtol=0, atol=1e-7)
    for entry in (periodyn.shooting, periodyn.ihb):
        with pytest.raises(InputError, match="rheo_linear_dae"):
            entry(pendulum_from_elements(samples=16).at(omega), omega)
    with pytest.raises(InputError, match="element model"):
        periodyn.continuation(pendulum_from_elements(samples=16), (omega, 1.1 * omega))
