"""Harmonic balance with too few harmonics gave amplitudes several times off with no sign
(pendulum l = 3.11 m, r = 4.28 m, e = 0.115, zeta = 0.022 at 0.9 omega0, m = 1: 5.26 rad
against 5.95 by integration; found by benchmarks/property_run.py). The harmonics left out
are now estimated (periodyn.harmonic.truncation), recorded per sweep point and warned
about; the reference here is eq. (29) integrated with SciPy's DOP853."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import periodyn
from periodyn.examples import pendulum
from periodyn.harmonic.truncation import BALANCE_TRUNCATION_TOL, BalanceTruncationWarning

CASE = {"length": 3.11, "radius": 4.28, "eccentricity": 0.1147, "zeta": 0.022}
W = 0.9 * math.sqrt(9.81 / CASE["length"])


def integrated_amplitude(omega: float, length: float, radius: float, eccentricity: float, zeta: float) -> float:
    """Half peak-to-peak of the periodic orbit of eq. (29): x0 = (I - Phi)^-1 x_p(T)."""
    w0, rho = math.sqrt(9.81 / length), radius / length

    def rhs(t, y):
        k = w0 ** 2 + (1 + eccentricity) * rho * omega ** 2 * math.cos(omega * t)
        A = np.array([[0.0, 1.0], [-k, -2 * zeta * w0]])
        b = np.array([0.0, -2 * zeta * w0 * omega + (1 - eccentricity) * rho * omega ** 2 * math.sin(omega * t)])
        X = y[2:].reshape(2, 2)
        return np.r_[A @ y[:2] + b, (A @ X).ravel()]

    T = 2 * math.pi / omega
    end = solve_ivp(rhs, (0, T), np.r_[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], method="DOP853", rtol=1e-11, atol=1e-13).y[:, -1]
    x0 = np.linalg.solve(np.eye(2) - end[2:].reshape(2, 2), end[:2])
    orbit = solve_ivp(lambda t, y: rhs(t, np.r_[y, np.eye(2).ravel()])[:2], (0, T), x0, method="DOP853",
                      rtol=1e-11, atol=1e-13, t_eval=np.linspace(0, T, 400)).y[0]
    return 0.5 * np.ptp(orbit)


@pytest.fixture(scope="module")
def reference():
    return integrated_amplitude(W, **CASE)


def test_too_few_harmonics_warn_and_enough_agree_with_integration(reference):
    system = pendulum(samples=48, **CASE).at(W)
    with pytest.warns(BalanceTruncationWarning, match=r"harmonics = 1 leaves out harmonics .* increase harmonics"):
        coarse = periodyn.periodic_solution(system, 1)
    assert abs(coarse.amplitude()[0] / reference - 1) > 0.1     # the answer the warning is about
    with warnings.catch_warnings():
        warnings.simplefilter("error", BalanceTruncationWarning)
        fine = periodyn.periodic_solution(system, 12)
    assert fine.amplitude()[0] == pytest.approx(reference, rel=1e-4)


def test_a_sweep_records_the_indicator_per_point_and_warns(reference):
    model = pendulum(samples=48, **CASE)
    with pytest.warns(BalanceTruncationWarning, match="1 of 2 speeds"):
        coarse = periodyn.sweep(model, [W, 0.1 * W], 1, stability=False, progress=False)
    truncation = coarse["balance_truncation"].values
    assert truncation[0] > BALANCE_TRUNCATION_TOL > truncation[1]
    assert coarse["balance_truncation"].attrs["units"] == "1"
    fine = periodyn.sweep(model, [W], 12, stability=False, progress=False)
    assert fine["balance_truncation"].values[0] < BALANCE_TRUNCATION_TOL
    assert fine["amplitude"].values[0, 0] == pytest.approx(reference, rel=1e-4)


def test_the_indicator_bounds_the_amplitude_error_of_random_pendulums():
    """Below the tolerance the amplitude agrees with integration to a few times it."""
    rng = np.random.default_rng(4)
    for _ in range(6):
        length = rng.uniform(0.3, 3.0)
        case = {"length": length, "radius": rng.uniform(0.1, 1.2) * length, "eccentricity": rng.uniform(0, 0.9),
                "zeta": rng.uniform(0.01, 0.2)}
        w = rng.uniform(0.2, 1.4) * math.sqrt(9.81 / length)
        system = pendulum(samples=48, **case).at(w)
        ref = integrated_amplitude(w, **case)
        for m in (1, 3, 6):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                amp = periodyn.periodic_solution(system, m).amplitude()[0]
            if not any(issubclass(c.category, BalanceTruncationWarning) for c in caught):
                assert amp == pytest.approx(ref, rel=5 * BALANCE_TRUNCATION_TOL)


def test_constant_coefficients_leave_nothing_out():
    p = 16
    system = periodyn.RheoLinear.from_samples(np.ones((p, 1, 1)), np.full((p, 1, 1), 0.2), np.full((p, 1, 1), 4.0),
                                              np.cos(2 * np.pi * np.arange(p) / p)[:, None], 1.3)
    with warnings.catch_warnings():
        warnings.simplefilter("error", BalanceTruncationWarning)
        sol = periodyn.periodic_solution(system, 1)
    assert sol.amplitude()[0] == pytest.approx(1 / abs(4.0 - 1.3 ** 2 + 0.2j * 1.3), rel=1e-12)


def test_each_speed_indicator_is_independent_of_the_speeds_beside_it():
    """A sweep's chunks hold different speeds: for the same harmonics, every speed's indicator
    must equal, to the bit, the one computed for that speed alone (the coefficient band, the
    forced harmonics and the coefficients at omega are per speed), as serial and parallel
    sweeps are bit-identical."""
    from periodyn.speeds import SpeedSolver

    speeds = np.linspace(150.0, 300.0, 7)
    solver = SpeedSolver(periodyn.examples.slider_crank(samples=32), 3, stability=False)
    q = solver._balance(speeds)[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BalanceTruncationWarning)
        together = solver._truncation(q, speeds)
        alone = np.concatenate([solver._truncation(q[i:i + 1], speeds[i:i + 1]) for i in range(speeds.size)])
    assert np.isfinite(together).all() and np.array_equal(together, alone)
