"""Averaging transient (eq. 24) against direct integration of the linear equations."""

import numpy as np
import pytest

import periodyn


def stiff_two_dof(omega=1.0):
    """Modes at about 20 and 45 rad/s (well above omega, well separated, 1-2 % damped),
    small periodic parts: the regime in which first-order averaging is valid."""
    K0 = np.array([[500.0, -100.0], [-100.0, 1800.0]])
    return periodyn.RheoLinear.from_functions(
        lambda t: np.eye(2) * (1 + 0.02 * np.cos(omega * t)),
        lambda t: np.diag([0.5, 1.5]),
        lambda t: K0 * (1 + 0.05 * np.sin(omega * t)),
        lambda t: np.array([np.sin(omega * t), 0.5 * np.cos(2 * omega * t)]),
        omega, 32)


def test_averaging_follows_integration_when_valid():
    sys = stiff_two_dof()
    sol = periodyn.periodic_solution(sys, 8)
    t = np.linspace(0, sys.period, 400)
    y0 = np.array([0.01, -0.005, 0.0, 0.1])
    avg = periodyn.transient(sys, sol, y0, t)
    ref = periodyn.transient(sys, sol, y0, t, method="integrate")
    transient_size = np.abs(ref.q - ref.periodic_q).max()
    assert np.abs(avg.q - ref.q).max() < 0.05 * transient_size
    # and it is a genuine transient: it decays towards the periodic solution
    late = t > 0.8 * sys.period
    assert np.abs(ref.q - ref.periodic_q)[late].max() < 0.5 * transient_size


def test_starting_on_the_periodic_solution_gives_no_transient():
    sys = stiff_two_dof()
    sol = periodyn.periodic_solution(sys, 10)
    t = np.linspace(0, 2 * sys.period, 50)
    y0 = np.concatenate([sol(0.0)[0], sol.velocity(0.0)[0]])
    for method in ("averaging", "integrate"):
        tr = periodyn.transient(sys, sol, y0, t, method=method)
        np.testing.assert_allclose(tr.q, tr.periodic_q, atol=1e-9 * np.abs(tr.periodic_q).max())


def test_bad_initial_state_and_times():
    sys = stiff_two_dof()
    sol = periodyn.periodic_solution(sys, 4)
    with pytest.raises(periodyn.InputError, match="shape \\(4,\\)"):
        periodyn.transient(sys, sol, [0.0, 0.0], [0.0, 1.0])
    with pytest.raises(periodyn.InputError, match="increasing"):
        periodyn.transient(sys, sol, np.zeros(4), [1.0, 0.5])
    with pytest.raises(periodyn.InputError, match="averaging"):
        periodyn.transient(sys, sol, np.zeros(4), [0.0, 1.0], method="magic")
