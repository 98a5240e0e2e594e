"""EGA-IHB periodic solutions against independent time-domain solutions of the same DAE."""

import numpy as np
import pytest

from periodyn import RheoLinear, characteristic_exponents
from periodyn.dae import DAE
from periodyn.nonlinear import ihb
from periodyn.nonlinear.ihb_solver import IHBProblem
from periodyn.errors import ConvergenceError, InputError
from periodyn.examples.dae_examples import rod_pendulum, slider_chain_pendulum, slider_rod_pendulum
from periodyn.numerics.integration import integrate
from periodyn.nonlinear import shooting
from periodyn.numerics.integration import steady_state


@pytest.fixture(scope="module")
def rod_steady():
    """Rod pendulum (eps1 = 0.3 N m s, f = 0.8 N m) swinging 0.61 rad at 3.4 rad/s:
    steady state by integrating from rest until the state repeats to 1e-10."""
    s = rod_pendulum(eps1=0.3, f=0.8)
    w = 3.4
    q, qd, periods, _ = steady_state(s, w, tol=1e-10, rtol=1e-11, atol=1e-13)
    T = 2 * np.pi / w
    t = np.linspace(0, T, 41)
    th = integrate(s, w, (0, T), q, qd, t_eval=t, rtol=1e-11, atol=1e-13)
    return s, w, th, periods


def test_ihb_equals_long_time_integration_and_converges_in_H(rod_steady):
    s, w, th, periods = rod_steady
    assert periods > 20  # a genuine transient decayed (28 periods)
    errs, lam_errs = [], []
    for H in (1, 3, 5, 7, 9):
        sol = ihb(s, w, H, stability=None)
        errs.append(np.abs(sol(th.t) - th.q).max())
        lam_errs.append(np.abs(sol.lam(th.t) - th.lam).max())
    # errors fall with H (spectral convergence) down to the integration tolerance
    assert all(b < 0.1 * a for a, b in zip(errs[:-1], errs[1:]))
    assert errs[-1] < 1e-9  # rad / m; measured 3.5e-10 (H = 9)
    assert all(b < 0.1 * a for a, b in zip(lam_errs[:-1], lam_errs[1:]))
    assert lam_errs[-1] < 1e-6  # N, with constraint forces ~ 10 N; measured 3.8e-7
    assert np.abs(th.lam).max() > 5.0


def test_ihb_multipliers_equal_direct_integration_multipliers(rod_steady):
    s, w, th, _ = rod_steady
    sol = ihb(s, w, 9)
    sh = shooting(s, w, initial=(th.q[0], th.qd[0]))
    np.testing.assert_allclose(np.sort_complex(sol.multipliers), np.sort_complex(sh.multipliers), atol=1e-6)
    # rod pendulum: damping acts on the single independent coordinate, |mu| = exp(-eps T / (2 I_pivot))
    np.testing.assert_allclose(np.abs(sol.multipliers), np.exp(-0.3 / (2 / 3) * 2 * np.pi / w), rtol=1e-8)
    assert sol.stable and sh.stable


def test_ihb_hill_and_monodromy_agree():
    s = slider_rod_pendulum()
    mono = ihb(s, 6.0, 10, stability="magnus")
    hill = ihb(s, 6.0, 10, stability="hill")
    np.testing.assert_allclose(np.sort(np.abs(mono.multipliers)), np.sort(np.abs(hill.multipliers)), atol=1e-7)


def test_shared_hill_magnus_and_monodromy_give_the_multipliers_of_direct_integration():
    """The slider-rod orbit linearized to a periodyn.RheoLinear: its multipliers by dense Hill,
    Magnus and the DOP853 monodromy of the shared linear core equal the monodromy of the
    full non-linear DAE integrated directly (shooting) to 1e-8."""
    s = slider_rod_pendulum()
    sol = ihb(s, 6.0, 12, tol=1e-11, stability=None)
    sh = shooting(s, 6.0, initial=sol, tol=1e-11)
    direct = np.sort_complex(sh.multipliers)
    prob = IHBProblem(s, 12)
    X = prob.from_solution(sol)
    lin = prob.linearization(X, 6.0)
    assert isinstance(lin.rheo, RheoLinear) and lin.rheo.n == 2 and lin.rheo.omega == 6.0
    for method in ("dense", "magnus", "monodromy"):
        exps = prob.exponents(X, 6.0, method=method)
        assert exps.method == method and exps.period == sol.period
        np.testing.assert_allclose(np.sort_complex(exps.multipliers), direct, atol=1e-8)
    via_core = characteristic_exponents(lin.rheo, 12, method="dense")
    np.testing.assert_allclose(np.sort_complex(via_core.multipliers), direct, atol=1e-8)


def test_slider_rod_ihb_vs_shooting_including_constraint_forces():
    s = slider_rod_pendulum()
    sol = ihb(s, 6.0, 12)
    sh = shooting(s, 6.0, initial=sol)
    t = np.linspace(0, sol.period, 30)
    assert np.abs(sol(t) - sh(t)).max() < 1e-8
    assert np.abs(sol.lam(t) - sh.lam(t)).max() < 1e-7
    np.testing.assert_allclose(np.sort(np.abs(sol.multipliers)), np.sort(np.abs(sh.multipliers)), atol=1e-6)
    assert sol.residual < 1e-8 and sh.residual < 1e-9


def test_chain_orbit_is_periodic_under_integration():
    """3-rod slider-chain: integrating the DAE for one period from the IHB state stays on the IHB orbit."""
    s = slider_chain_pendulum(n_rods=3)
    w = 5.0
    sol = ihb(s, w, 10)
    t = np.linspace(0, sol.period, 21)
    th = integrate(s, w, (0, sol.period), sol(0.0)[0], sol.velocity(0.0)[0], t_eval=t, rtol=1e-10, atol=1e-12)
    assert np.abs(th.q - sol(t)).max() < 1e-7
    assert np.abs(th.lam - sol.lam(t)).max() < 1e-5 * np.abs(th.lam).max()
    assert s.n == 11 and s.m == 7 and len(sol.multipliers) == 8


def test_user_dae_pendulum_equals_builder():
    """The same rod pendulum written by hand through periodyn.DAE (complex-step Jacobians)."""
    m, l, eps, f = 1.0, 1.0, 0.04, 0.15

    def force(q, qd, t, w):
        return np.array([0.0 * q[0], -m * 9.81 + 0.0 * q[1], -eps * qd[2] + f * np.cos(w * t)])

    def phi(q, t, w):
        return np.array([q[0] - l / 2 * np.cos(q[2]), q[1] - l / 2 * np.sin(q[2])])

    def phi_q(q, t, w):
        return np.array([[1, 0, l / 2 * np.sin(q[2])], [0, 1, -l / 2 * np.cos(q[2])]])

    user = DAE(np.diag([m, m, m * l * l / 12]), force, phi, constraint_jacobian=phi_q, q0=[0, -0.5, -np.pi / 2])
    a = ihb(user, 3.0, 6)
    b = ihb(rod_pendulum(), 3.0, 6)
    np.testing.assert_allclose(a.harmonics, b.harmonics, atol=1e-12)
    np.testing.assert_allclose(np.abs(a.lambda_harmonics), np.abs(b.lambda_harmonics), atol=1e-10)
    sh = shooting(user, 3.0, initial=a)  # constraint_rates derived from the Hessian (scleronomic)
    assert np.abs(sh(np.linspace(0, 1, 7)) - a(np.linspace(0, 1, 7))).max() < 1e-6


def test_nonconverged_newton_raises_and_bad_input_is_refused():
    with pytest.raises(ConvergenceError) as info:
        ihb(rod_pendulum(), 3.8, 8, max_iter=1, stability=None)
    assert info.value.iterations == 1 and info.value.residual > 0
    with pytest.raises(InputError):
        ihb(rod_pendulum(), -1.0, 4)
    with pytest.raises(InputError):
        ihb(rod_pendulum(), 3.0, 4, samples=9)
    with pytest.raises(InputError):
        rod_pendulum().with_parameters(nope=1.0)


@pytest.mark.slow
def test_41_body_chain_ihb_orbit_under_integration_and_hill_vs_monodromy():
    """40-rod slider-chain (n = 122, m = 81), H = 10: one period of integration from the IHB
    state stays on the orbit; Hill and monodromy multipliers agree."""
    s = slider_chain_pendulum()
    w = 5.0
    sol = ihb(s, w, 10, stability="magnus")
    t = np.linspace(0, sol.period, 11)
    th = integrate(s, w, (0, sol.period), sol(0.0)[0], sol.velocity(0.0)[0], t_eval=t, rtol=1e-10, atol=1e-12)
    assert np.abs(th.q - sol(t)).max() < 1e-6
    assert np.abs(th.lam - sol.lam(t)).max() < 1e-4 * np.abs(th.lam).max()
    hill = ihb(s, w, 10, initial=sol, stability="hill")
    assert len(sol.multipliers) == 82
    # both truncate (Hill: 16 harmonics, Magnus: 256 steps); measured difference 2.2e-6
    np.testing.assert_allclose(np.sort(np.abs(sol.multipliers))[-10:], np.sort(np.abs(hill.multipliers))[-10:], atol=5e-6)
