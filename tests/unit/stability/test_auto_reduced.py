"""The method "auto" of a sweep takes the method "reduced" on element models where it is
estimated cheaper, records it per speed, and meets the full model's certified ladder."""

import numpy as np
import pytest

import periodyn
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
from periodyn.model.linearization import omega_split
from periodyn.speeds import SpeedSolver
from periodyn.stability.magnus import MagnusLadder
from periodyn.stability.reduced import AUTO_MIN_COORDINATES, reduced_pays


def crank(elements: int):
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=elements))
    return omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=elements), 64)


@pytest.fixture(scope="module")
def large():
    return crank(16)


def test_auto_takes_the_reduced_method_on_a_large_element_model(large):
    """16 rod elements (32 coordinates): "auto" solves by "reduced" (and the reduced HB),
    the same exponents as the method asked for by name, within its bound of the full
    model's certified ladder (an independent method on all 32 coordinates)."""
    w = np.array([180.0, 260.0])
    assert large.n >= AUTO_MIN_COORDINATES
    auto = SpeedSolver(large, 12)
    res = auto.solve_many(w)
    assert list(res.method) == ["reduced", "reduced"] and reduced_pays(auto.speed_stability, w).all()
    assert np.all(res.reduced_modes > 0) and np.all(res.balance_modes > 0) and np.all(res.residual < 1e-9)
    named = SpeedSolver(large, 12, stability="reduced").solve_many(w)
    np.testing.assert_array_equal(res.exponents, named.exponents)
    est = MagnusLadder(*large._power_spectra[:3]).solve(w, np.inf)
    assert est.accepted.all()
    G, full = res.max_real * 2 * np.pi / w, est.exponents.real.max(axis=1) * 2 * np.pi / w
    assert np.all(np.abs(G - full) <= res.stability_error_bound + est.error)
    assert np.all(res.stability_error_bound <= 1e-6)


def test_auto_keeps_the_full_ladder_on_small_models():
    """8 rod elements (16 coordinates, below AUTO_MIN_COORDINATES): the full ladder, as before."""
    model = crank(8)
    res = SpeedSolver(model, 12).solve_many(np.array([200.0]))
    assert res.method[0] == "magnus" and res.reduced_modes[0] == 0 and res.balance_modes[0] == 0


def test_a_default_sweep_records_the_choice(large):
    ds = periodyn.sweep(large, np.array([220.0]), 12, 64, progress=False)
    assert list(ds["stability_method"].values) == ["reduced"]
    assert ds["reduced_modes"].values[0] > 0 and np.isfinite(ds["stability_error_bound"].values[0])
