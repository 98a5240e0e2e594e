"""The per-model speed solver (Hill/HB blocks as polynomials in omega) against the
direct per-speed path and the monodromy matrix."""

import numpy as np
import pytest

import periodyn
from periodyn.speeds import SpeedSolver, solve_point
from periodyn.examples.chain import parametric_chain
import periodyn.harmonic.batch_balance as batch_module

from ..conftest import assert_same_spectrum


@pytest.mark.parametrize("form", ["direct", "inverse-mass"])
@pytest.mark.parametrize("builder,m,speeds", [
    (lambda: periodyn.examples.pendulum(samples=36), 8, (0.7, 2.3, 3.4, 4.4)),
    (lambda: parametric_chain(3, samples=64), 10, (11.0, 40.0, 97.0)),
])
def test_speed_solver_equals_direct_path(builder, m, speeds, form):
    model = builder()
    solver = SpeedSolver(model, m, form=form)
    for w in speeds:
        a, b = solver.solve(w), solve_point(model.at(w), m, form=form)
        np.testing.assert_allclose(a.output_harmonics, b.output_harmonics, atol=1e-12 * np.abs(b.output_harmonics).max())
        np.testing.assert_allclose(a.amplitude, b.amplitude, rtol=1e-10)
        assert_same_spectrum(a.multipliers, b.multipliers, atol=1e-10)
        assert a.stable == b.stable


def test_speed_solver_sparse_exponents_match_monodromy():
    model = parametric_chain(4, samples=64)
    solver = SpeedSolver(model, 12, stability="sparse")
    for w in (15.0, 60.0):
        mono = periodyn.characteristic_exponents(model.at(w), 0, "monodromy")
        assert_same_spectrum(solver.solve(w).multipliers, mono.multipliers, atol=1e-8)


def test_speed_solver_rejects_bad_speed():
    solver = SpeedSolver(periodyn.examples.pendulum(), 4)
    with pytest.raises(periodyn.InputError, match="positive"):
        solver.solve(-1.0)


def test_speed_solver_magnus_matches_dense_hill_on_the_slider_crank():
    model = periodyn.examples.slider_crank(damping=0.02, samples=64)
    fast, hill = SpeedSolver(model, 12, stability="magnus"), SpeedSolver(model, 12, stability="dense")
    for w in (150.0, 205.0, 268.0):
        a, b = fast.solve(w), hill.solve(w)
        assert_same_spectrum(a.multipliers, b.multipliers, atol=1e-6)
        assert a.stable == b.stable
        np.testing.assert_array_equal(a.output_harmonics, b.output_harmonics)


@pytest.mark.parametrize("builder,m,method,speeds", [
    (lambda: periodyn.examples.pendulum(samples=36), 8, "auto", np.linspace(0.3, 4.6, 23)),
    (lambda: periodyn.examples.slider_crank(damping=0.01, samples=64), 12, "magnus", np.linspace(150, 300, 7)),
    (lambda: parametric_chain(3, samples=64), 10, "sparse", np.array([11.0, 97.0])),
])
def test_solve_many_equals_speed_by_speed(builder, m, method, speeds):
    """Stacked chunks (and the speed-by-speed paths they fall back to) give each speed the
    result of solving it alone."""
    model = builder()
    solver = SpeedSolver(model, m, stability=method)
    batch = solver.solve_many(speeds)
    assert len(batch) == speeds.size and (batch.message == "").all()
    for i, w in enumerate(speeds):
        one, direct = solver.solve(w), solve_point(model.at(w), m, stability=method)
        np.testing.assert_allclose(batch.output_harmonics[i], one.output_harmonics, rtol=0,
                                   atol=1e-13 * np.abs(one.output_harmonics).max())
        assert_same_spectrum(batch.multipliers[i], one.multipliers, atol=1e-12)
        np.testing.assert_allclose(batch.amplitude[i], direct.amplitude, rtol=1e-9)
        assert_same_spectrum(batch.multipliers[i], direct.multipliers, atol=1e-9)
        assert batch.stable[i] == direct.stable
        assert batch.residual[i] < 1e-12


def test_solve_many_rejects_bad_speeds():
    solver = SpeedSolver(periodyn.examples.pendulum(), 4)
    with pytest.raises(periodyn.InputError, match="positive finite"):
        solver.solve_many([1.0, float("nan")])
    with pytest.raises(periodyn.InputError, match="1-D"):
        solver.solve_many([[1.0, 2.0]])
    with pytest.raises(periodyn.InputError, match="numbers"):
        solver.solve_many(["fast"])


def test_hb_storage_follows_the_coefficient_band():
    """Narrow coefficient bands are never stored dense (band storage per speed); only a
    band coupling (nearly) all harmonics is, for the stacked real solve."""
    narrow = SpeedSolver(parametric_chain(3, samples=64), 10)
    assert narrow.pattern.narrow and narrow.batch_balance == "banded" and narrow.storage.kind == "banded"
    assert narrow.harmonic.banded_terms.shape[1:] == (2 * narrow.pattern.half_bandwidth + 1, narrow.pattern.size)
    wide = SpeedSolver(periodyn.examples.slider_crank(damping=0.02, samples=64), 12, stability=False)
    assert not wide.pattern.narrow and wide.batch_balance == "dense" and wide.storage.kind == "dense"


def _forced_oscillator(k):
    """q'' + k q = cos(theta), undamped: resonant where (l omega)^2 = k."""
    p = 16
    theta = 2 * np.pi * np.arange(p) / p
    return periodyn.OmegaSplitModel.from_samples(np.ones((p, 1, 1)), [], [np.full((p, 1, 1), float(k))],
                                                 [np.cos(theta)[:, None]])


def _on_path(solver, path, monkeypatch):
    """Make the solver take HB path "banded", "dense", None (per speed) or "iterative"
    (the dense path's GMRES with a reference LU, here at any size)."""
    if path == "iterative":
        monkeypatch.setattr(batch_module, "ITERATIVE_MIN", 1)
    solver.batch_balance = "dense" if path == "iterative" else path


@pytest.mark.parametrize("path", ["banded", "dense", None, "iterative"])
def test_undamped_resonance_names_the_speed(path, monkeypatch):
    """q'' + q = cos(theta): the HB matrix is exactly singular where l omega = 1. In a
    batch of speeds that speed is a failed point with the reason (the others are solved,
    by each HB path: jitted banded, stacked dense, per speed, GMRES); alone it raises."""
    solver = SpeedSolver(_forced_oscillator(1.0), 3, stability=False)
    _on_path(solver, path, monkeypatch)
    batch = solver.solve_many([0.3, 0.7, 1.0, 2.0])  # (l omega)^2 = 1 only at omega = 1 for |l| <= 3
    assert "singular at omega = 1 rad/s" in batch.message[2] and "add damping or move omega" in batch.message[2]
    assert list(batch.message != "") == [False, False, True, False]
    assert np.isnan(batch.amplitude[2]).all() and np.isfinite(batch.amplitude[[0, 1, 3]]).all()
    np.testing.assert_allclose(batch.amplitude[[0, 1, 3], 0], 1 / np.abs(1 - np.array([0.3, 0.7, 2.0]) ** 2),
                               rtol=1e-12)
    with pytest.raises(periodyn.ConvergenceError, match="singular at omega = 1 rad/s"):
        solver.solve(1.0)
    with pytest.raises(periodyn.InputError, match="singular at omega = 1 rad/s"):
        periodyn.periodic_solution(solver.model.at(1.0), 3)


@pytest.mark.parametrize("path", ["banded", "dense", None, "iterative"])
def test_speed_within_rounding_of_an_undamped_resonance_is_a_failed_point(path, monkeypatch):
    """q'' + 2 q = cos(theta) near omega = sqrt(2): not exactly singular in floating point,
    but the forcing is amplified ~1/|2 - omega^2| times. Within 1e-12 of the resonance
    (amplification 1e12 > 4.5e9) the point fails with the reason; 1e-6 away the large
    response (3.5e5) is solved and exact to 1e-8."""
    solver = SpeedSolver(_forced_oscillator(2.0), 3, stability=False)
    _on_path(solver, path, monkeypatch)
    w = np.sqrt(2.0) * np.array([1.0, 1.0 + 1e-12, 1.0 + 1e-6])
    batch = solver.solve_many(w)
    for i in (0, 1):
        assert "nearly singular" in batch.message[i] and "undamped resonance" in batch.message[i]
        assert "add damping or move omega" in batch.message[i] and np.isnan(batch.amplitude[i]).all()
    assert batch.message[2] == ""
    np.testing.assert_allclose(batch.amplitude[2, 0], 1 / abs(2 - w[2] ** 2), rtol=1e-8)
    with pytest.raises(periodyn.ConvergenceError, match="nearly singular"):
        periodyn.periodic_solution(solver.model.at(w[1]), 3)


def test_sweep_across_an_undamped_resonance_flags_only_that_point():
    """A sweep of the undamped forced oscillator through its resonance (and a speed
    within rounding of it): the near-resonant point is failed with its reason in the
    dataset (status 1, message), the speeds around it are solved, with stability."""
    w = np.sort(np.r_[np.linspace(1.0, 2.0, 9), np.sqrt(2.0)])
    ds = periodyn.sweep(_forced_oscillator(2.0), w, 3, stability="dense")
    bad = np.isclose(ds.omega.values, np.sqrt(2.0), rtol=0, atol=1e-15)
    assert bad.sum() == 1 and ds.status.values[bad][0] == 1
    assert "undamped resonance" in str(ds.message.values[bad][0])
    assert (ds.status.values[~bad] == 0).all() and np.isfinite(ds.amplitude.values[~bad]).all()
    assert np.isnan(ds.amplitude.values[bad]).all()


def test_unresolved_clusters_are_reported_per_speed(monkeypatch):
    """A speed whose Hill clusters cannot be resolved is a failed point with a message
    (NaN exponents, not stable), never a result; its neighbours in the chunk are kept."""
    import periodyn.stability.hill as hill
    from periodyn.errors import ConvergenceError

    real_batch = hill.select_clusters_batch

    def lose_one(lam, X, omegas, m, n, count, exps, cents, edge, found):
        real_batch(lam, X, omegas, m, n, count, exps, cents, edge, found)
        found[omegas == 2.0] = count - 1  # pretend omega = 2 resolved one cluster too few

    monkeypatch.setattr(hill, "select_clusters_batch", lose_one)
    solver = SpeedSolver(periodyn.examples.pendulum(samples=36), 6, stability="dense")  # the Hill path
    batch = solver.solve_many([1.0, 2.0, 3.0])
    assert list(batch.message != "") == [False, True, False]
    assert "resolved 1 of 2 exponent clusters" in batch.message[1] and "increase harmonics" in batch.message[1]
    assert np.isnan(batch.exponents[1]).all() and np.isnan(batch.max_real[1]) and not batch.stable[1]
    assert np.isfinite(batch.exponents[[0, 2]]).all()
    with pytest.raises(ConvergenceError, match="exponent clusters"):
        solver.solve(2.0)


def test_dense_hill_beyond_the_terms_budget_goes_speed_by_speed(monkeypatch):
    """A model whose real first-order Hill terms would exceed DENSE_TERMS_BYTES builds its
    dense Hill matrix per speed (the terms are never formed) and gets the stacked path's
    exponents."""
    import periodyn.stability.batch as batch

    model = periodyn.examples.slider_crank(damping=0.02, samples=32)
    speeds = np.array([150.0, 220.0, 300.0])
    stacked = SpeedSolver(model, 12, stability="dense").solve_many(speeds)
    monkeypatch.setattr(batch, "DENSE_TERMS_BYTES", 0.0)
    solver = SpeedSolver(model, 12, stability="dense")
    one_by_one = solver.solve_many(speeds)
    assert not solver.dense_hill and "real_first_order_terms" not in solver.harmonic.__dict__
    assert (one_by_one.message == "").all()
    for a, b in zip(stacked.exponents, one_by_one.exponents):
        assert_same_spectrum(a, b, atol=1e-10 * np.abs(a).max())
    np.testing.assert_array_equal(stacked.stable, one_by_one.stable)
