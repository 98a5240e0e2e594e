"""Element-built models against analytic results: the pinned-pinned rod's bending
frequency (two elements: 832 rad/s as in Schwab & Meijaard 2001; refinement towards the
continuum pi^2 sqrt(EI/(rho A L^4))), and the elliptic pendulum against eq. (29)."""

import numpy as np
import pytest

from periodyn.examples.elliptic_pendulum import pendulum_from_elements
from periodyn.examples.slider_crank_rod import (EI, MASS_PER_LENGTH, ROD_LENGTH, first_bending_frequency,
                                            slider_crank_model)

CONTINUUM = np.pi**2 * np.sqrt(EI / (MASS_PER_LENGTH * ROD_LENGTH**4))


def test_two_element_rod_frequency_is_the_papers_832():
    w = first_bending_frequency(slider_crank_model(rod_elements=2))
    assert w == pytest.approx(832.0, rel=5e-3)
    assert w == pytest.approx(832.5405847933948, rel=1e-10)  # golden value of this model
    assert CONTINUUM == pytest.approx(829.27, abs=0.01)


def test_rod_frequency_converges_to_the_continuum_at_fourth_order():
    n = np.array([2, 4, 8])
    err = np.array([first_bending_frequency(slider_crank_model(rod_elements=int(k))) for k in n]) - CONTINUUM
    assert np.all(err > 0) and np.all(np.diff(err) < 0)
    order = np.log2(err[:-1] / err[1:])
    assert np.all(order > 3.8), order


@pytest.mark.parametrize("ratio", [0.3, 0.5, 0.91, 1.3])
def test_element_pendulum_equals_eq29_at_every_sample(ratio):
    l, r, e, zeta, g = 1.0, 0.5, 0.5, 0.01, 9.81
    w0, rho = np.sqrt(g / l), r / l
    w = ratio * w0
    model = pendulum_from_elements(length=l, radius=r, eccentricity=e, zeta=zeta, g=g, samples=24)
    system = model.at(w)
    theta = 2 * np.pi * np.arange(24) / 24
    np.testing.assert_allclose(system.mass[:, 0, 0], 1.0, atol=1e-10)
    np.testing.assert_allclose(system.damping[:, 0, 0], 2 * zeta * w0, atol=1e-10)
    np.testing.assert_allclose(system.stiffness[:, 0, 0], w0**2 + (1 + e) * rho * w**2 * np.cos(theta), atol=1e-10)
    np.testing.assert_allclose(system.force[:, 0], -2 * zeta * w0 * w + (1 - e) * rho * w**2 * np.sin(theta),
                               atol=1e-10)


def test_element_pendulum_is_scale_free_in_mass_and_matches_other_geometry():
    """Another bob mass and geometry still give eq. (29) (normalised by m l^2)."""
    l, r, e, zeta, g = 2.0, 0.3, 0.25, 0.05, 9.81
    w0, rho = np.sqrt(g / l), r / l
    w = 1.7
    system = pendulum_from_elements(length=l, radius=r, eccentricity=e, zeta=zeta, g=g, mass=3.0, samples=16).at(w)
    theta = 2 * np.pi * np.arange(16) / 16
    np.testing.assert_allclose(system.stiffness[:, 0, 0], w0**2 + (1 + e) * rho * w**2 * np.cos(theta), atol=1e-10)
    np.testing.assert_allclose(system.force[:, 0], -2 * zeta * w0 * w + (1 - e) * rho * w**2 * np.sin(theta),
                               atol=1e-10)


def test_element_pendulum_sweep_equals_the_analytic_pendulum():
    """The periodic amplitude and exponents of the element-built pendulum equal those of
    the analytic eq. (29) model (periodyn.examples.pendulum)."""
    import periodyn
    from periodyn.examples.pendulum_equation import pendulum
    analytic, built = pendulum(samples=32), pendulum_from_elements(samples=32)
    w0 = np.sqrt(9.81)
    for ratio in (0.45, 0.8, 1.1, 1.25):
        a, b = analytic.at(ratio * w0), built.at(ratio * w0)
        pa, pb = periodyn.periodic_solution(a, 8), periodyn.periodic_solution(b, 8)
        np.testing.assert_allclose(pb.amplitude(), pa.amplitude(), rtol=1e-9)
        ea, eb = periodyn.characteristic_exponents(a, 8), periodyn.characteristic_exponents(b, 8)
        assert eb.max_real == pytest.approx(ea.max_real, rel=1e-8, abs=1e-10)
