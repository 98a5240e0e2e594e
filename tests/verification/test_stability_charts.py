"""Two-parameter stability charts (periodyn.stability.charts) on the elliptic pendulum,
eq. (29), over the damping zeta: every followed boundary point equals a bisection at its
own zeta, sits where the monodromy matrix (DOP853) has a multiplier at exactly +1 or -1 (the
other is exp(-2 zeta w0 T) by Liouville: one coordinate, constant damping), the zones shrink
with damping, the 1:1 zone closes at a tip that the monodromy confirms, and the chart's
dataset reads back unchanged."""

import numpy as np
import pytest

from periodyn.errors import InputError
from periodyn.examples import pendulum
from periodyn.results import load, save
from periodyn.stability.boundaries import stability_boundaries
from periodyn.stability.chart_data import (ChartOptions, chart_dataset, chart_from_dataset, checks_from_dataset)
from periodyn.stability.charts import check_chart, stability_chart
from periodyn.stability.methods import characteristic_exponents

W0 = np.sqrt(9.81)
ZETA = np.linspace(0.005, 0.12, 6)
WINDOW = np.linspace(0.5, 2.0, 31) * W0


def model_at(zeta):
    return pendulum(zeta=float(zeta), samples=64)


@pytest.fixture(scope="module")
def chart():
    return stability_chart(model_at, WINDOW, ZETA, ChartOptions(12), name="zeta")


def test_two_boundary_curves_the_one_zone_closing_at_a_tip(chart):
    assert len(chart.boundaries) == 2
    zone, principal = sorted(chart.boundaries, key=lambda b: b.omega[0])
    assert zone.ends == ("range", "range") and principal.ends == ("range", "range")
    assert zone.tips.size == 1 and principal.tips.size == 0
    assert set(zone.kind) == {"fold"} and set(principal.kind) == {"period-doubling"}
    tip = zone.tips[0]
    assert (zone.side[:tip] == -1).all() and (zone.side[tip + 1:] == 1).all() and (principal.side == -1).all()


def test_every_point_equals_the_bisection_at_its_damping(chart):
    """Per-parameter bisection (Brent between the speeds of a fine grid) at each zeta of the grid."""
    grid = np.linspace(0.5, 2.0, 61) * W0
    for zeta in ZETA:
        found = stability_boundaries(model_at(zeta).at, grid, 12, "auto", xtol=1e-11)
        rows = chart.at(zeta)
        assert [(k, s) for _, k, s in rows] == [(b.kind, 1 if b.becomes_stable else -1) for b in found]
        np.testing.assert_allclose([w for w, _, _ in rows], [b.omega for b in found], rtol=1e-8)


def test_boundary_points_have_a_monodromy_multiplier_at_plus_or_minus_one(chart):
    """Liouville: mu1 mu2 = exp(-2 zeta w0 T), so on a boundary the multipliers are +-1 and
    +-exp(-2 zeta w0 T); the monodromy matrix by DOP853 at every third point says so."""
    for b in chart.boundaries:
        for p, w, kind in list(zip(b.parameter, b.omega, b.kind))[::3]:
            mu = characteristic_exponents(model_at(p).at(w), 1, "monodromy").multipliers
            sign = 1.0 if kind == "fold" else -1.0
            critical = mu[np.argmin(np.abs(mu - sign))]
            assert abs(critical - sign) < 1e-6, (p, w, mu)
            np.testing.assert_allclose(np.prod(mu).real, np.exp(-2 * p * W0 * 2 * np.pi / w), rtol=1e-7)


def test_zones_shrink_with_damping(chart):
    zone, principal = sorted(chart.boundaries, key=lambda b: b.omega[0])
    tip = zone.tips[0]
    left, right = zone.omega[:tip], zone.omega[tip + 1:][::-1]
    np.testing.assert_array_equal(zone.parameter[:tip], zone.parameter[tip + 1:][::-1])
    assert np.all(np.diff(right - left) < 0)             # the 1:1 zone narrows as zeta grows
    assert np.all(np.diff(principal.omega) > 0)          # the principal zone's lower edge rises


def test_the_tip_is_where_the_zone_closes_by_the_monodromy(chart):
    zone = min(chart.boundaries, key=lambda b: b.omega[0])
    p, w = zone.parameter[zone.tips[0]], zone.omega[zone.tips[0]]
    assert ZETA[2] < p < ZETA[3]
    below = characteristic_exponents(model_at(p * (1 - 1e-3)).at(w), 1, "monodromy").max_real
    above = [characteristic_exponents(model_at(p * (1 + 1e-3)).at(w * f), 1, "monodromy").max_real
             for f in (0.98, 0.99, 1.0, 1.01, 1.02)]
    assert below > 0 and max(above) < 0


def test_check_chart_agrees_and_the_dataset_reads_back(chart, tmp_path):
    checks = check_chart(model_at, chart, points=2)
    assert len(checks) == 4 and all(c.check.agrees for c in checks)
    save(chart_dataset(chart, checks), tmp_path / "chart.nc")
    ds = load(tmp_path / "chart.nc")
    back = chart_from_dataset(ds)
    assert back.options == chart.options and back.seeds == chart.seeds and back.parameter_name == "zeta"
    for a, b in zip(back.boundaries, chart.boundaries, strict=True):
        for name in ("parameter", "omega", "side"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
        assert list(a.kind) == list(b.kind) and a.ends == b.ends
    assert [(c.boundary, c.parameter, c.check.agrees, c.check.max_real_inside) for c in checks_from_dataset(ds)] == \
        [(c.boundary, c.parameter, c.check.agrees, c.check.max_real_inside) for c in checks]


def test_bad_input_is_refused_with_the_fix():
    with pytest.raises(InputError, match="increasing"):
        stability_chart(model_at, WINDOW[::-1], ZETA, ChartOptions(4))
    with pytest.raises(InputError, match="not values of the parameter grid"):
        stability_chart(model_at, WINDOW, ZETA, ChartOptions(4), seeds=[0.5])
    with pytest.raises(InputError, match="unknown method"):
        ChartOptions(4, method="newton")
    with pytest.raises(InputError, match="xtol"):
        ChartOptions(4, xtol=0.5)
