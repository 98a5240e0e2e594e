"""Shooting: variational monodromy against finite differences and Hill, implicit vs explicit
integration, multiple vs single shooting, cold starts, angles modulo 2 pi, failures."""

import numpy as np
import pytest

from periodyn.nonlinear import ihb
from periodyn.nonlinear.ihb_solver import IHBProblem
from periodyn.errors import ConvergenceError, InputError
from periodyn.examples.dae_examples import duffing, rod_pendulum, slider_rod_pendulum
from periodyn.nonlinear import shooting
from periodyn.nonlinear.shooting_solver import ShootingProblem
from periodyn.numerics.variational import flow


def fd_monodromy(prob, X, omega, h=1e-6):
    """Monodromy in independent coordinates by central differences, all 4r + 1 perturbed
    trajectories in one batch (one step sequence, so integration errors cancel)."""
    P = prob.system.parameters
    k = prob.size
    S = np.vstack([X, X + h * np.eye(k), X - h * np.eye(k)])
    Y0 = np.array([np.concatenate(prob.full_state(s, omega, P)) for s in S])
    f = flow(prob.system, omega, Y0, 0.0, prob.span, rtol=prob.rtol, atol=prob.atol)
    n = prob.system.n
    ends = np.array([np.concatenate([y[:n][prob.ind[0]], y[n:][prob.ind[0]]]) for y in f.y])
    return (ends[1:k + 1] - ends[k + 1:]).T / (2 * h)


@pytest.fixture(scope="module")
def slider_rod():
    s = slider_rod_pendulum()
    sol = ihb(s, 6.0, 12, tol=1e-11, stability=None)
    return s, sol, shooting(s, 6.0, initial=sol, tol=1e-11)


def test_variational_monodromy_equals_finite_differences_and_hill(slider_rod):
    s, sol, sh = slider_rod
    q, qd = sh(0.0)[0], sh.velocity(0.0)[0]
    prob = ShootingProblem(s, q)
    X = prob.state(q, qd)
    mono = prob.monodromy(X, 6.0)
    np.testing.assert_allclose(mono, fd_monodromy(prob, X, 6.0), atol=1e-8 * np.abs(mono).max())
    hill = IHBProblem(s, 12).exponents(IHBProblem(s, 12).from_solution(sol), 6.0, method="dense")
    np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(mono)), np.sort_complex(hill.multipliers), atol=1e-8)


def test_radau_with_analytic_jacobian_gives_the_same_orbit_and_multipliers(slider_rod):
    s, _, sh = slider_rod
    radau = shooting(s, 6.0, initial=sh, tol=1e-10, integrator="Radau", rtol=1e-10)
    t = np.linspace(0, sh.period, 7)
    assert np.abs(radau(t) - sh(t)).max() < 1e-8
    np.testing.assert_allclose(np.sort_complex(radau.multipliers), np.sort_complex(sh.multipliers), atol=1e-7)


@pytest.mark.parametrize("system, omega, segments", [(duffing(0.05, 0.5, 0.5), 1.3, 4), (slider_rod_pendulum(), 6.0, 3)])
def test_multiple_shooting_gives_the_single_shooting_orbit(system, omega, segments):
    single = shooting(system, omega, tol=1e-11)
    multi = shooting(system, omega, initial=single, segments=segments, tol=1e-11)
    t = np.linspace(0, single.period, 11)
    assert np.abs(multi(t) - single(t)).max() < 1e-9
    assert multi.residual <= 1e-11 and multi.iterations <= 2
    np.testing.assert_allclose(np.sort_complex(multi.multipliers), np.sort_complex(single.multipliers), atol=1e-9)


def test_cold_start_from_rest_converges_for_duffing_near_resonance():
    """x'' + 0.1 x' + x + 0.5 x^3 = 0.5 cos(1.02 t) from rest (Newton from rest alone fails)."""
    s = duffing(0.05, 0.5, 0.5)
    with pytest.raises(ConvergenceError):  # Newton alone from rest
        ShootingProblem(s, np.zeros(1)).newton(np.zeros(2), 1.02)
    sol = shooting(s, 1.02)
    assert sol.residual <= 1e-9
    # independent check: one period of direct integration from the orbit's start returns to it
    y0 = np.concatenate([sol(0.0)[0], sol.velocity(0.0)[0]])
    end = flow(s, 1.02, y0[None], 0.0, 2 * np.pi, rtol=1e-12, atol=1e-13).y[0]
    assert np.abs(end - y0).max() < 1e-8
    assert sol.stable and sol.amplitude()[0] > 0.5


def test_two_pi_shifted_angle_is_the_same_orbit():
    s = rod_pendulum(eps1=0.3, f=0.8)
    ref = shooting(s, 3.4, cyclic=("phi_rod",))
    q, qd = ref(0.0)[0], ref.velocity(0.0)[0]
    q[2] += 2 * np.pi  # the same configuration, the angle shifted by a turn
    shifted = shooting(s, 3.4, initial=(q, qd), cyclic=("phi_rod",))
    np.testing.assert_allclose(shifted.harmonics, ref.harmonics, atol=1e-9)
    assert -np.pi < shifted.mean[2] <= np.pi


def test_failed_start_is_reported_with_what_was_tried():
    s = duffing(0.05, 0.5, 0.5)
    with pytest.raises(ConvergenceError, match="tried: Newton after settling 2 periods.*settle_periods=") as err:
        shooting(s, 1.02, settle_periods=2, max_iter=2)
    assert err.value.iterations == 2 and err.value.residual > 1e-9
    with pytest.raises(InputError, match="cyclic"):
        shooting(s, 1.02, cyclic=("theta",))
    with pytest.raises(InputError, match="segments"):
        shooting(s, 1.02, segments=0)
