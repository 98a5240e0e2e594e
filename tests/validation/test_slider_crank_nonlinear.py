"""Slider-crank with a flexible rod, full non-linear equations (4) against the linearized
ones (Schwab & Meijaard 2001, sec. 4.2, Fig. 4): at 150 rad/s, 2 % damping, the steady
midpoint deflection of the non-linear model agrees with the linearized one "within a
few percent"; the non-linear periodic solution by EGA-IHB is confirmed by shooting."""

import numpy as np
import pytest

import periodyn
from periodyn.examples.slider_crank import slider_crank, slider_crank_nonlinear
from periodyn.periodic import half_range_and_mean
from periodyn.spectra import fourier_coefficients

OMEGA = 150.0  # rad/s


@pytest.fixture(scope="module")
def orbits():
    system = slider_crank_nonlinear(0.02)
    guess = periodyn.ihb(system, OMEGA, 12, stability=None, tol=1e-5)
    shot = periodyn.shooting(system, OMEGA, initial=guess, tol=1e-7, rtol=1e-9)
    return system, guess, shot


def _midpoint(system, orbit, samples=64):
    t = np.arange(samples) * orbit.period / samples
    return periodyn.element_outputs(system.equations.model, OMEGA, t, orbit(t))[:, 0]


def test_shooting_confirms_the_ihb_orbit(orbits):
    system, guess, shot = orbits
    t = np.linspace(0.0, shot.period, 17)
    # IHB truncates at 12 harmonics: its spectral tail bounds the difference
    assert guess.tail < 1e-3
    np.testing.assert_allclose(shot(t), guess(t), rtol=0, atol=guess.tail * np.abs(shot(t)).max())
    assert shot.stable and np.abs(shot.stability.multipliers).max() < 0.6


def test_steady_midpoint_deflection_agrees_with_the_linearized_within_a_few_percent(orbits):
    system, _, shot = orbits
    lin = periodyn.periodic_solution(slider_crank(0.02, 64).at(OMEGA), 12)
    y_nl = _midpoint(system, shot)
    amp_nl = half_range_and_mean(fourier_coefficients(y_nl[:, None], 31))[0][0]
    amp_lin = lin.output_amplitude()[0]
    assert abs(amp_nl / amp_lin - 1) < 0.03
    assert 0.001 < amp_lin < 0.01  # the paper's Fig. 4 scale (deflection / rod length)
