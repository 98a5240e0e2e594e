"""periodyn.periodic.PeriodicSolution: one result for HB, IHB and shooting."""

import numpy as np
import pytest

import periodyn
from periodyn.nonlinear import ihb
from periodyn.examples.dae_examples import inverted_pendulum, slider_rod_pendulum
from periodyn.nonlinear import shooting
from periodyn.periodic import PeriodicSolution
from periodyn.numerics.spectra import to_samples


def _dense_half_range(sol, samples=2 ** 20):
    """Half peak-to-peak from 2^20 samples per period (grid error ~ (2 pi / 2^20)^2 / 2 ~ 2e-11 relative)."""
    q = to_samples(sol.harmonics, samples)
    return 0.5 * (q.max(axis=0) - q.min(axis=0))


@pytest.mark.parametrize("solve", [
    lambda: ihb(slider_rod_pendulum(), 6.0, 12, stability=None),
    lambda: shooting(slider_rod_pendulum(), 6.0, initial=ihb(slider_rod_pendulum(), 6.0, 12, stability=None)),
    lambda: ihb(inverted_pendulum(), 10.0, 8, subharmonic=1, stability=None),
])
def test_amplitude_from_refined_extrema_equals_dense_sampling(solve):
    """IHB and shooting amplitudes come from the refined extrema of the series: equal to a
    2^20-sample reference to 1e-10 (the former 512-sample max - min was off by up to 2e-5)."""
    sol = solve()
    ref = _dense_half_range(sol)
    np.testing.assert_allclose(sol.amplitude(), ref, rtol=0, atol=1e-10 * max(1.0, ref.max()))
    coarse = to_samples(sol.harmonics, 512)
    assert np.abs(0.5 * (coarse.max(0) - coarse.min(0)) - ref).max() > 1e-9  # what the refinement gains


def test_one_type_for_all_methods_with_the_shared_stability_verdict():
    s = slider_rod_pendulum()
    a = ihb(s, 6.0, 10)
    b = shooting(s, 6.0, initial=a)
    lin = periodyn.periodic_solution(periodyn.examples.pendulum().at(3.0), 6)
    for sol, method in ((a, "ihb"), (b, "shooting"), (lin, "hb")):
        assert type(sol) is PeriodicSolution and sol.method == method
    assert periodyn.PeriodicSolution is PeriodicSolution
    assert isinstance(a.stability, periodyn.FloquetExponents) and isinstance(b.stability, periodyn.FloquetExponents)
    assert a.stable == a.stability.stable and np.array_equal(a.multipliers, a.stability.multipliers)
    assert a.stability.period == a.period and b.stability.period == b.period
    assert lin.stability is None and lin.multipliers is None and lin.stable is None
    # outputs default to the coordinates; constraint forces by the same convention
    np.testing.assert_array_equal(a.output_harmonics, a.harmonics)
    t = np.linspace(0, a.period, 7)
    assert np.abs(a.lam(t) - b.lam(t)).max() < 1e-6 and a.lam(t).shape == (7, s.m)


def test_subharmonic_convention():
    """harmonics l of omega/nu: a nu = 2 orbit built from a T-orbit (even harmonics only) is the same function."""
    s = inverted_pendulum()
    a = ihb(s, 9.0, 6, stability=None)
    c = np.zeros((25, 3), complex)
    c[12 + 2 * np.arange(-6, 7)] = a.harmonics
    from dataclasses import replace
    b = replace(a, harmonics=c, subharmonic=2)
    t = np.linspace(0, 2 * a.period, 13)
    np.testing.assert_allclose(b(t), a(t), atol=1e-14)
    np.testing.assert_allclose(b.velocity(t), a.velocity(t), atol=1e-12)
    assert b.period == 2 * a.period and np.allclose(b.amplitude(), a.amplitude(), atol=1e-14)
