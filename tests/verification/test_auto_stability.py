"""Stability method "auto" with Magnus: its verdicts against dense Hill and the DOP853
monodromy on every shipped rheo-linear sweep file and at the boundaries of the
pendulum's unstable bands, and its step-doubling error estimate against the reference."""

import numpy as np
import pytest
from scipy.optimize import brentq

import periodyn
from periodyn.speeds import SpeedSolver
from periodyn.studies.spec import load_sweep_file, project_root
from periodyn.stability.floquet import STABILITY_TOL
from periodyn.stability.magnus import MagnusLadder

SHIPPED = ("pendulum", "slider_crank", "slider_crank_elements", "elliptic_pendulum_elements")


def _growth(system) -> float:
    """log max|mu| per period by the DOP853 monodromy (the reference)."""
    return periodyn.characteristic_exponents(system, 0, "monodromy").max_real * system.period


@pytest.mark.parametrize("name", SHIPPED)
def test_auto_verdicts_equal_dense_hill_on_every_shipped_sweep(name):
    spec = load_sweep_file(project_root() / "sweeps" / f"{name}.toml")
    plan = spec.plan()
    model = plan.model(**{k: v[-1] for k, v in plan.parameters.items()}) if plan.parameters else plan.model
    auto = SpeedSolver(model, spec.harmonics).solve_many(plan.omega)
    dense = SpeedSolver(model, spec.harmonics, stability="dense").solve_many(plan.omega)
    assert (auto.message == "").all() and (dense.message == "").all()
    np.testing.assert_array_equal(auto.stable, dense.stable)
    assert set(auto.method) <= {"magnus", "dense"} and "magnus" in set(auto.method)
    period = 2 * np.pi / plan.omega
    np.testing.assert_allclose(auto.max_real * period, dense.max_real * period, atol=1e-5)


def test_auto_verdicts_at_the_pendulum_band_boundaries():
    """Each boundary of the unstable bands in 0.5-1.4 omega0 is found by root finding on
    the DOP853 growth; speeds at relative offsets 1e-2 .. 1e-7 on both sides get the
    reference verdict from auto (Magnus where certified, dense Hill otherwise); at the
    boundaries themselves Magnus cannot certify a verdict and dense Hill serves."""
    model = periodyn.examples.pendulum(samples=64)
    w0 = model.metadata["omega0"]
    grid = np.linspace(0.5, 1.4, 91) * w0
    growth = np.array([_growth(model.at(w)) for w in grid]) - STABILITY_TOL
    edges = [brentq(lambda w: _growth(model.at(w)) - STABILITY_TOL, a, b, xtol=1e-13 * w0)
             for a, b, ga, gb in zip(grid[:-1], grid[1:], growth[:-1], growth[1:]) if ga * gb < 0]
    assert len(edges) >= 3  # both ends of the band near omega0 and the start of the next
    solver = SpeedSolver(model, 12)
    offsets = np.array([1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7])
    speeds = np.concatenate([e * (1 + np.concatenate([-offsets, offsets])) for e in edges])
    batch = solver.solve_many(speeds)
    reference = np.array([_growth(model.at(w)) <= STABILITY_TOL for w in speeds])
    dense = SpeedSolver(model, 12, stability="dense").solve_many(speeds).stable
    np.testing.assert_array_equal(batch.stable, reference)
    np.testing.assert_array_equal(batch.stable, dense)
    assert "magnus" in set(batch.method)
    at_edges = solver.solve_many(np.array(edges))  # growth = the threshold: no margin to certify
    assert (at_edges.method == "dense").all()


def test_magnus_error_estimate_bounds_the_error_against_the_reference():
    model = periodyn.examples.slider_crank(damping=0.02, samples=64)
    ladder = MagnusLadder(*model._power_spectra[:3])
    speeds = np.array([150.0, 190.0, 240.0, 300.0])
    est = ladder.solve(speeds, np.full(speeds.size, np.inf))
    assert est.accepted.all() and (est.error <= STABILITY_TOL).all()  # damped: growth below 1 per period
    for w, exps, error in zip(speeds, est.exponents, est.error):
        reference = periodyn.characteristic_exponents(model.at(w), 0, "monodromy")
        got = np.sort(np.exp(exps.real * 2 * np.pi / w))  # moduli of the multipliers
        want = np.sort(np.abs(reference.multipliers))
        # the DOP853 reference (rtol 1e-11 per step) is itself good to a few 1e-9 per period
        assert abs(np.log(got[-1] / want[-1])) <= error + 5e-9
        assert np.abs(got - want).max() / want[-1] <= error + 5e-9


def test_stiff_element_model_certified_at_the_first_comparison_and_within_its_estimate():
    """The slider-crank with 8 rod elements (stiff: balanced step generators of 177-353
    at 32 steps) starts at 32 steps; at 300 rad/s it certifies at the first comparison
    (32 and 64 steps), at 150 rad/s that difference (4e-6) exceeds the tolerance and it
    certifies at 128 steps. The certified multiplier moduli agree with a 2048-step Magnus
    reference of both orders within the estimated error (the reference's own error is
    below 1e-11 per period)."""
    from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
    from periodyn.model.linearization import omega_split

    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=8))
    model = omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=8), 64)
    spectra = model._power_spectra[:3]
    speeds = np.array([150.0, 300.0])
    ladder = MagnusLadder(*spectra)
    est = ladder.solve(speeds, np.full(2, np.inf))
    assert (ladder.first_rungs(speeds, 4) == 32).all()
    assert est.accepted.all() and est.steps.tolist() == [128, 64] and (est.order == 4).all()
    fine4, fine6 = (MagnusLadder(*spectra, order=k)._moduli(speeds, 2048, k)[1] for k in (4, 6))
    assert np.abs(fine4 - fine6).max() <= 1e-11 * fine6.max()
    for got, want, error in zip(np.sort(np.exp(est.exponents.real * 2 * np.pi / speeds[:, None])), fine6, est.error):
        assert abs(np.log(got[-1] / want[-1])) <= error
        assert np.abs(got - want).max() / want[-1] <= error


def test_auto_falls_back_to_hill_when_magnus_cannot_be_afforded():
    model = periodyn.examples.pendulum(samples=64)
    ladder = MagnusLadder(*model._power_spectra[:3])
    est = ladder.solve(np.array([5.0]), np.array([0.0]))
    assert not est.accepted[0] and est.steps[0] == 0
