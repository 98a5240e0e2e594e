"""Stability chart of the Cardan shaft (Schwab & Meijaard 2001, sec. 4.4) over the
misalignment alpha (periodyn.stability.charts): followed from alpha = pi/4 down to pi/6 the
four boundaries equal the speed sweep's bisection (0.6447-0.6780 and 0.7827-0.9168
omega/omega_b, README) and a bisection at pi/6 itself, with the same types, and the
monodromy matrix puts a multiplier on the unit circle there; followed further down, the
first zone closes at a tip (alpha = 0.3312) that the monodromy confirms, narrowing
monotonically on the way. The slow test follows both zones to their tips at several
dampings: the misalignment at which a zone closes scales as damping^(1/k) for a zone of
order k in the excitation (undamped width ~ alpha^k, and a zone opens where that width
exceeds one proportional to the damping), k = 2 for the first zone and 1 for the second."""

import numpy as np
import pytest

from periodyn.examples.cardan import cardan_shaft
from periodyn.stability.boundaries import check_boundary, StabilityBoundary, stability_boundaries
from periodyn.stability.chart_data import ChartOptions
from periodyn.stability.charts import stability_chart
from periodyn.stability.methods import characteristic_exponents

SWEEP_BISECTION = (0.6447, 0.6780, 0.7827, 0.9168)   # omega/omega_b at alpha = pi/6 (README, m = 12, 64 samples)


def model_at(alpha, damping=0.01):
    return cardan_shaft(float(alpha), damping=damping, samples=64)


@pytest.fixture(scope="module")
def omega_b():
    return model_at(np.pi / 6).metadata["omega_b"]


def test_boundaries_at_pi_over_6_equal_the_sweep_bisection(omega_b):
    """Followed in one step from pi/4 (seeded there by bisection on 12 speeds); the
    bisection at pi/6 brackets each boundary between two speeds 0.005-0.01 omega_b apart.
    Both use "auto" (a Magnus ladder that picks its steps per speed, certified to 1e-6 per
    period), so they agree to that ladder's error (3.5e-8 relative here), not to xtol."""
    chart = stability_chart(model_at, np.linspace(0.55, 0.97, 12) * omega_b, np.array([np.pi / 6, np.pi / 4]),
                            ChartOptions(12), seeds=[np.pi / 4], name="alpha")
    rows = chart.at(np.pi / 6)
    ratios = np.array([w for w, _, _ in rows]) / omega_b
    np.testing.assert_allclose(ratios, SWEEP_BISECTION, atol=1e-4)
    assert [(k, s) for _, k, s in rows] == [("fold", -1), ("fold", 1), ("neimark-sacker", -1), ("neimark-sacker", 1)]
    model = model_at(np.pi / 6)
    grid = np.array([0.64, 0.65, 0.675, 0.685, 0.78, 0.79, 0.91, 0.92]) * omega_b
    found = stability_boundaries(model.at, grid, 12, "auto", xtol=1e-11)
    np.testing.assert_allclose([w for w, _, _ in rows], [b.omega for b in found], rtol=1e-6)
    for w, kind, side in rows:
        check = check_boundary(model.at, StabilityBoundary(w, kind, side > 0), 1e-3)
        assert check.agrees, check
        mu = characteristic_exponents(model.at(w), 1, "monodromy").multipliers
        assert abs(np.abs(mu).max() - 1.0) < 1e-6


def test_the_first_zone_narrows_and_closes_at_a_tip(omega_b):
    grid = np.array([0.30, 0.36, 0.42, 0.48, np.pi / 6])
    chart = stability_chart(model_at, np.linspace(0.6, 0.75, 8) * omega_b, grid, ChartOptions(12),
                            seeds=[np.pi / 6], name="alpha")
    (zone,) = chart.boundaries
    assert zone.ends == ("range", "range") and zone.tips.size == 1 and set(zone.kind) == {"fold"}
    tip = zone.tips[0]
    p, w = zone.parameter[tip], zone.omega[tip]
    left, right = zone.omega[:tip], zone.omega[tip + 1:][::-1]
    assert np.all(np.diff(right - left) < 0)        # narrower at every step towards the tip
    assert 0.36 > p > 0.30
    inside = characteristic_exponents(model_at(p * (1 + 1e-3)).at(w), 1, "monodromy").max_real
    closed = [characteristic_exponents(model_at(p * (1 - 1e-3)).at(w * f), 1, "monodromy").max_real
              for f in (0.99, 1.0, 1.01)]
    assert inside > 0 and max(closed) < 0


def _tips(damping, window, grid):
    wb = model_at(np.pi / 6).metadata["omega_b"]
    chart = stability_chart(lambda a: model_at(a, damping), np.linspace(*window, 16) * wb, grid, ChartOptions(12),
                            seeds=[grid[-1]], name="alpha")
    return [b.parameter[b.tips[0]] for b in chart.boundaries if b.tips.size]


@pytest.mark.slow
def test_zones_close_as_alpha_falls_at_damping_to_the_power_one_over_their_order():
    """k = log 4 / log(alpha_tip(zeta) / alpha_tip(zeta / 4)). Measured: the second zone
    0.9995 (tips 0.027563, 0.0068863 at zeta = 0.01, 0.0025): first order, its width ~ alpha;
    the first zone 2.21 (zeta = 0.01 / 0.0025, tips 0.33117, 0.17702) and 2.07 (0.0025 /
    0.000625, tip 0.090561): second order, approached as the tips fall (the excitation is
    tan(alpha) sqrt(1 - sin^2 alpha cos^2 theta), linear in alpha only asymptotically)."""
    grid = np.linspace(0.05, np.pi / 4, 8)
    first = [_tips(z, (0.45, 0.735), grid)[0] for z in (0.01, 0.0025, 0.000625)]
    second = [_tips(z, (0.80, 0.99), np.linspace(0.002, 0.2, 8))[0] for z in (0.01, 0.0025)]
    k1 = [np.log(4.0) / np.log(a / b) for a, b in zip(first[:-1], first[1:])]
    k2 = np.log(4.0) / np.log(second[0] / second[1])
    assert abs(k1[1] - 2.0) < abs(k1[0] - 2.0) < 0.25
    assert abs(k2 - 1.0) < 1e-2
