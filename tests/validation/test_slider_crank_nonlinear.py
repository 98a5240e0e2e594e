"""Slider-crank with a flexible rod, full non-linear equations (4) against the linearized
ones (Schwab & Meijaard 2001, sec. 4.2, Fig. 4): at 150 rad/s, 2 % damping, the steady
midpoint deflection of the non-linear model agrees with the linearized one "within a
few percent"; the non-linear periodic solution by EGA-IHB is confirmed by shooting, and
the fixed-step implicit shooting by adaptive shooting."""

import numpy as np
import pytest

import periodyn
from periodyn.examples.slider_crank_rod import slider_crank, slider_crank_nonlinear
from periodyn.periodic import half_range_and_mean
from periodyn.numerics.spectra import fourier_coefficients

from ..conftest import assert_same_spectrum

OMEGA = 150.0  # rad/s


@pytest.fixture(scope="module")
def orbits():
    system = slider_crank_nonlinear(0.02)
    guess = periodyn.ihb(system, OMEGA, 12, stability=None, tol=1e-5)
    shot = periodyn.shooting(system, OMEGA, initial=guess, tol=1e-10, rtol=1e-11)
    return system, guess, shot


def _midpoint(system, orbit, samples=64):
    t = np.arange(samples) * orbit.period / samples
    return periodyn.element_outputs(system.equations.model, orbit.omega, t, orbit(t))[:, 0]


def test_shooting_confirms_the_ihb_orbit(orbits):
    system, guess, shot = orbits
    t = np.linspace(0.0, shot.period, 17)
    # IHB truncates at 12 harmonics: its spectral tail bounds the difference
    assert guess.tail < 1e-3
    np.testing.assert_allclose(shot(t), guess(t), rtol=0, atol=guess.tail * np.abs(shot(t)).max())
    assert shot.stable and np.abs(shot.stability.multipliers).max() < 0.6


def test_implicit_shooting_agrees_with_adaptive_shooting_within_its_error_estimate(orbits):
    """integrator="implicit" (trapezoidal map, Richardson-extrapolated, started from the
    linearized harmonic balance) against DOP853 shooting at rtol 1e-11: harmonics within
    the reported error estimate (measured 0.089 of it at 256 steps, 0.022 at 512: fourth
    order, ratio 14.9), multipliers against DOP853's monodromy and the Hill exponents of
    the IHB orbit (measured 2.9e-3 at 256 steps, 1.8e-4 at 512; second order would give
    2.7e-2 and 6.7e-3)."""
    system, guess, shot = orbits
    start = periodyn.periodic_solution(slider_crank(0.02, 64).at(OMEGA), 12)
    hill = periodyn.ihb(system, OMEGA, 12, initial=guess, stability="hill")
    assert_same_spectrum(hill.multipliers, shot.multipliers, 1e-9)
    errors = []
    for steps, mu_tol in ((256, 5e-3), (512, 3e-4)):
        sol = periodyn.shooting(system, OMEGA, initial=start, integrator="implicit", steps=steps)
        ref = shot.harmonics[shot.m - sol.m:shot.m + sol.m + 1]
        errors.append(np.abs(sol.harmonics - ref).max() / np.abs(ref).max())
        assert errors[-1] < 0.15 * sol.discretization_error
        assert_same_spectrum(sol.multipliers, shot.multipliers, mu_tol)
        assert_same_spectrum(sol.multipliers, hill.multipliers, mu_tol)
        assert sol.stable and sol.residual <= 1e-9
    assert errors[0] / errors[1] > 12  # 2^4 = 16 for fourth order


def test_steady_midpoint_deflection_agrees_with_the_linearized_within_a_few_percent(orbits):
    system, _, shot = orbits
    lin = periodyn.periodic_solution(slider_crank(0.02, 64).at(OMEGA), 12)
    y_nl = _midpoint(system, shot)
    amp_nl = half_range_and_mean(fourier_coefficients(y_nl[:, None], 31))[0][0]
    amp_lin = lin.output_amplitude()[0]
    assert abs(amp_nl / amp_lin - 1) < 0.03
    assert 0.012 < amp_lin < 0.0135  # Fig. 4: about 0.0127 (deflection / rod length, half peak-to-peak)


@pytest.mark.parametrize("window, paper", [((203.0, 210.0), 206.0), ((265.0, 271.0), 267.0)])
def test_nonlinear_resonance_peaks_sit_below_the_linearized_ones(window, paper):
    """Fig. 5: the non-linear peaks (near 206 and 267 rad/s in the paper) are lower than the
    linearized ones; peak speeds from IHB continuation (steps < 0.3 rad/s there) against a
    0.05 rad/s linearized grid."""
    system = slider_crank_nonlinear(0.02)
    branch = periodyn.continuation(system, window, 12, stability=None, tol=1e-5, ds_max=0.05, max_points=400)
    assert branch.omega[-1] >= window[1] - 1e-9
    peaks_nl = [np.abs(_midpoint(system, s, 32)).max() for s in branch.solutions]
    j = int(np.argmax(peaks_nl))
    assert 0 < j < len(peaks_nl) - 1 and np.diff(branch.omega)[j - 1:j + 1].max() < 0.3
    lin = slider_crank(0.02, 64)
    grid = np.arange(*window, 0.05)
    peaks_lin = [np.abs(periodyn.periodic_solution(lin.at(w), 12).outputs(np.arange(64) * 2 * np.pi / (64 * w))).max()
                 for w in grid]
    i = int(np.argmax(peaks_lin))
    assert peaks_nl[j] < 0.97 * peaks_lin[i]
    assert abs(branch.omega[j] - paper) < 1.5
