"""Fixed-step implicit shooting (``shooting(..., integrator="implicit")``): the discrete
monodromy of the trapezoidal map against exact monodromies (second-order convergence),
against finite differences of the map itself on the non-linear slider-crank, and the
periodic response against harmonic balance within the reported error estimate."""

import numpy as np
import pytest
import scipy.linalg as sla

import periodyn
from periodyn.errors import InputError
from periodyn.examples.slider_crank_rod import slider_crank_nonlinear
from periodyn.nonlinear.implicit import ImplicitMap
from periodyn.dae import rheo_linear_dae
from periodyn.numerics.spectra import fourier_coefficients

W = 2.0  # rad/s


def _oscillator(samples=16):
    """q'' + 0.1 q' + q = cos(omega t), constant coefficients."""
    th = 2 * np.pi * np.arange(samples) / samples
    one = np.ones((samples, 1, 1))
    return periodyn.RheoLinear.from_samples(one, 0.1 * one, one, np.cos(th)[:, None], W)


def _order(errors):
    return np.log2(np.array(errors[:-1]) / np.array(errors[1:]))


def test_discrete_monodromy_of_a_damped_oscillator_converges_at_second_order_to_expm():
    system = rheo_linear_dae(_oscillator())
    exact = sla.expm(np.array([[0.0, 1.0], [-1.0, -0.1]]) * 2 * np.pi / W)
    errors = [np.abs(ImplicitMap(system, W)(np.zeros(2), N)[1] - exact).max() for N in (32, 64, 128)]
    np.testing.assert_allclose(_order(errors), 2.0, atol=0.05)


def test_discrete_multipliers_of_the_linearized_pendulum_converge_at_second_order():
    omega = 0.6 * np.sqrt(9.81)
    rl = periodyn.examples.pendulum(samples=64).at(omega)
    ref = np.sort_complex(periodyn.characteristic_exponents(rl, 12, method="monodromy").multipliers)
    system = rheo_linear_dae(rl)
    errors = [np.abs(np.sort_complex(np.linalg.eigvals(ImplicitMap(system, omega)(np.zeros(2 * rl.n), N)[1])) - ref).max()
              for N in (64, 128, 256)]
    np.testing.assert_allclose(_order(errors), 2.0, atol=0.1)


def _plain_harmonics(system, omega, sol, steps):
    """Harmonics (as many as sol's) of the un-extrapolated orbit on ``steps`` steps."""
    pmap = ImplicitMap(system, omega)
    x = pmap.newton(np.concatenate([sol(0.0)[0], sol.velocity(0.0)[0]]), steps, 1e-12, 10).x
    return fourier_coefficients(pmap(x, steps)[0][:-1, :system.n], sol.m)


def test_forced_oscillator_orbit_matches_harmonic_balance_within_the_error_estimate():
    """The N-step orbit is off by its Richardson estimate (order 2), the returned
    extrapolated one by far less (order 4)."""
    rl = _oscillator()
    system = rheo_linear_dae(rl)
    exact = periodyn.periodic_solution(rl, 4)
    plain, extrapolated = [], []
    for steps in (32, 64, 128):
        sol = periodyn.shooting(system, W, integrator="implicit", steps=steps)
        ref = np.zeros_like(sol.harmonics)
        ref[sol.m - 4:sol.m + 5] = exact.harmonics
        scale = np.abs(ref).max()
        plain.append(np.abs(_plain_harmonics(system, W, sol, steps) - ref).max() / scale)
        extrapolated.append(np.abs(sol.harmonics - ref).max() / scale)
        assert 0.97 * sol.discretization_error < plain[-1] < 1.03 * sol.discretization_error  # 1.012 at 32
        assert extrapolated[-1] < 0.03 * sol.discretization_error  # 0.012 at 32
        assert sol.method == "shooting" and sol.stable
    np.testing.assert_allclose(_order(plain), 2.0, atol=0.05)
    np.testing.assert_allclose(_order(extrapolated), 4.0, atol=0.05)


def test_slider_crank_discrete_monodromy_equals_finite_differences_of_the_map():
    system = slider_crank_nonlinear(0.02)
    pmap = ImplicitMap(system, 150.0)
    s = np.zeros(2 * system.n)
    S = pmap(s, 64)[1]
    h = 1e-6
    fd = np.column_stack([(pmap(s + h * e, 64)[0][-1] - pmap(s - h * e, 64)[0][-1]) / (2 * h) for e in np.eye(s.size)])
    np.testing.assert_allclose(S, fd, rtol=0, atol=1e-5 * np.abs(S).max())


def test_implicit_shooting_refuses_other_systems_and_odd_steps():
    with pytest.raises(InputError, match="element models"):
        periodyn.shooting(periodyn.examples.pendulum_nonlinear(), 1.0, integrator="implicit")
    with pytest.raises(InputError, match="even"):
        periodyn.shooting(rheo_linear_dae(_oscillator()), W, integrator="implicit", steps=33)
    with pytest.raises(InputError, match="integrator"):
        periodyn.shooting(rheo_linear_dae(_oscillator()), W, integrator="euler")


def test_implicit_shooting_that_does_not_converge_is_reported():
    """Element pendulum near its resonance, one Newton update allowed: ConvergenceError
    with the residual and iteration count, never a solution."""
    from periodyn.errors import ConvergenceError
    from periodyn.examples.elliptic_pendulum import elliptic_pendulum_model

    with pytest.raises(ConvergenceError) as err:
        periodyn.shooting(elliptic_pendulum_model(), 0.95 * np.sqrt(9.81), integrator="implicit", max_iter=1, tol=1e-14)
    assert err.value.iterations == 1 and np.isfinite(err.value.residual) and err.value.residual > 1e-14
