"""Harmonic balance against independent solutions: the periodic orbit found by linear
shooting with the time integrator, the analytic FRF of a constant-coefficient system, and
the two balance forms against each other."""

import numpy as np
import pytest

import periodyn
from periodyn.stability.monodromy import integrate, monodromy_matrix

from ..conftest import two_dof_parametric


def periodic_orbit_by_integration(system, t):
    """y0 of the periodic orbit from y(T) = Phi y0 + y_f(T) = y0, then integrate."""
    n2 = 2 * system.n
    y_forced = integrate(system, np.zeros(n2), [0.0, system.period])[-1]
    y0 = np.linalg.solve(np.eye(n2) - monodromy_matrix(system), y_forced)
    return integrate(system, y0, t)


@pytest.fixture(scope="module")
def two_dof():
    sys = two_dof_parametric(omega=1.3, samples=64)
    t = np.linspace(0, sys.period, 41)
    return sys, t, periodic_orbit_by_integration(sys, t)


def test_pendulum_matches_integration_and_converges_in_m(pendulum_model):
    sys = pendulum_model.at(0.4 * pendulum_model.metadata["omega0"])
    t = np.linspace(0, sys.period, 37)
    ref = periodic_orbit_by_integration(sys, t)[:, 0]
    errors = []
    for m in (2, 3, 4, 5, 6, 10):
        sol = periodyn.periodic_solution(sys, m)
        errors.append(np.abs(sol(t)[:, 0] - ref).max() / np.abs(ref).max())
    assert errors[-1] < 1e-8  # the integrator's own accuracy is about 2e-10 here
    assert all(e2 < 0.05 * e1 for e1, e2 in zip(errors[:4], errors[1:5]))  # geometric convergence in m


@pytest.mark.parametrize("form", ["direct", "inverse-mass"])
def test_two_dof_time_varying_mass_matches_integration(two_dof, form):
    sys, t, ref = two_dof
    sol = periodyn.periodic_solution(sys, 14, form=form)
    err = np.abs(sol(t) - ref[:, :2]).max() / np.abs(ref[:, :2]).max()
    assert err < 1e-6
    assert np.abs(sol.velocity(t) - ref[:, 2:]).max() / np.abs(ref[:, 2:]).max() < 1e-6
    assert sol.residual < 1e-12


def test_forms_agree_once_converged(two_dof):
    sys, _, _ = two_dof
    a = periodyn.periodic_solution(sys, 16, form="direct")
    b = periodyn.periodic_solution(sys, 16, form="inverse-mass")
    np.testing.assert_allclose(a.harmonics, b.harmonics, atol=1e-9 * np.abs(a.harmonics).max())


def test_constant_coefficients_give_the_frequency_response():
    M = np.array([[2.0, 0.1], [0.1, 1.0]])
    C = np.array([[0.3, 0.0], [0.0, 0.1]])
    K = np.array([[5.0, -1.0], [-1.0, 3.0]])
    w = 1.7
    F1 = np.array([1.0, 0.5 - 0.2j])  # f = F1 e^{iwt} + c.c.
    sys = periodyn.RheoLinear.from_functions(lambda t: M, lambda t: C, lambda t: K,
                                             lambda t: 2 * (F1 * np.exp(1j * w * t)).real, w, 8)
    sol = periodyn.periodic_solution(sys, 3)
    q1 = np.linalg.solve(K - w**2 * M + 1j * w * C, F1)
    np.testing.assert_allclose(sol.harmonics[4], q1, rtol=1e-13)
    np.testing.assert_allclose(sol.amplitude(), 2 * np.abs(q1), rtol=1e-10)
    assert np.abs(np.delete(sol.harmonics, [2, 4], axis=0)).max() < 1e-14


def test_amplitude_is_half_the_range_of_a_fine_evaluation(two_dof):
    sys, _, _ = two_dof
    sol = periodyn.periodic_solution(sys, 10)
    t = np.linspace(0, sys.period, 20000, endpoint=False)
    q = sol(t)
    np.testing.assert_allclose(sol.amplitude(), 0.5 * (q.max(0) - q.min(0)), rtol=1e-7)
    np.testing.assert_allclose(sol.mean, q.mean(0), atol=1e-12)


def test_time_varying_output_maps_are_exact_products():
    w = 2.0
    G = lambda t: np.array([[np.cos(w * t), 1.0]])  # noqa: E731
    sys = periodyn.RheoLinear.from_functions(lambda t: np.eye(2), lambda t: 0.1 * np.eye(2),
                                             lambda t: np.diag([3.0, 5.0]),
                                             lambda t: np.array([np.sin(w * t), np.cos(2 * w * t)]), w, 32,
                                             output_maps=np.stack([G(tj) for tj in np.arange(32) * np.pi / 16 / w]),
                                             output_names=["y"])
    sol = periodyn.periodic_solution(sys, 4)
    t = np.linspace(0, sys.period, 50)
    direct = np.einsum("toj,tj->to", np.stack([G(tj) for tj in t]), sol(t))
    np.testing.assert_allclose(sol.outputs(t), direct, atol=1e-13)
