"""Slider-crank with flexible connecting rod, Schwab & Meijaard (2001) section 4.2,
Figs. 4-6: resonances near 1/5, 1/4 and 1/3 of the first bending frequency (832 rad/s)
in 150-300 rad/s, and the periodic midpoint deflection at omega = 150 rad/s checked
against direct integration of the linearized equations."""

import numpy as np
import pytest

import periodyn
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank, slider_crank_model
from periodyn.numerics.spectra import synthesize
from periodyn.stability.monodromy import integrate

OMEGA1 = 832.0  # rad/s, paper


@pytest.fixture(scope="module")
def sweep_1pct():
    model = slider_crank(0.01, 64)
    omega = np.arange(150.0, 300.01, 1.0)
    amp = np.array([periodyn.periodic_solution(model.at(w), 12).output_amplitude()[0] for w in omega])
    return omega, amp


def test_resonances_near_one_fifth_quarter_and_third_of_832(sweep_1pct):
    omega, amp = sweep_1pct
    inner = (amp[1:-1] > amp[:-2]) & (amp[1:-1] > amp[2:])
    peaks = omega[1:-1][inner]
    assert len(peaks) == 3, peaks
    w1 = first_bending_frequency(slider_crank_model())
    for peak, k in zip(peaks, (5, 4, 3)):
        # the mean stiffness over a revolution is a little lower than at dead centre
        assert 0.95 * w1 / k < peak < w1 / k, (peak, k)
        assert abs(peak - OMEGA1 / k) / (OMEGA1 / k) < 0.05


def test_periodic_deflection_at_150_agrees_with_direct_integration():
    """Fig. 4: 2 % damping, omega = 150 rad/s. Started on the harmonic-balance orbit, the
    direct integration of the linearized equations must stay on it for two periods."""
    system = slider_crank(0.02, 64).at(150.0)
    periodic = periodyn.periodic_solution(system, 12)
    T = 2 * np.pi / 150.0
    t = np.linspace(0, 2 * T, 401)
    y0 = np.concatenate([periodic(np.array([0.0]))[0], periodic.velocity(np.array([0.0]))[0]])
    y = integrate(system, y0, t)
    G = synthesize(system.spectra.outputs, 150.0 * t)
    deflection = np.einsum("tij,tj->ti", G, y[:, :system.n])[:, 0]
    np.testing.assert_allclose(periodic.outputs(t)[:, 0], deflection, atol=1e-4 * np.abs(deflection).max())
    amplitude = periodic.output_amplitude()[0]
    assert 0.010 < amplitude < 0.016  # Fig. 4: midpoint deflection of order 1e-2
