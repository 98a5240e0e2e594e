"""Hill's method with too few harmonics: its truncation indicator (the energy fraction of the
chosen eigenvectors in the outermost harmonics) refuses or flags the verdict, never silent.

The case: elliptic pendulum (eq. 29) with l = 2.4678 m, r = 2.2631 m, zeta = 0 at 4.2582 rad/s
(inside the principal parametric resonance) grows x18.2 per period by the DOP853 monodromy;
dense Hill with m = 2 called it stable."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from periodyn import characteristic_exponents
from periodyn.errors import ConvergenceError, InputError
from periodyn.examples import pendulum
from periodyn.results import STATUS_FAILED
from periodyn.speeds import SpeedSolver
from periodyn.stability.floquet import TRUNCATION_TOL, TruncationWarning

OMEGA = 4.2582


@pytest.fixture(scope="module")
def model():
    return pendulum(length=2.4678, radius=2.2631, zeta=0.0)


@pytest.fixture(scope="module")
def reference(model):
    return characteristic_exponents(model.at(OMEGA), 1, method="monodromy")


@pytest.mark.parametrize("method", ["dense", "sparse"])
def test_too_few_harmonics_are_refused_naming_the_fix(model, reference, method):
    assert not reference.stable and reference.max_multiplier == pytest.approx(18.2132, rel=1e-4)
    with pytest.raises(ConvergenceError, match=r"truncated .* increase harmonics .*truncation='warn'"):
        characteristic_exponents(model.at(OMEGA), 2, method=method)


def test_forced_truncated_verdict_warns_and_keeps_its_indicator(model, reference):
    with pytest.warns(TruncationWarning, match="harmonics = 2"):
        forced = characteristic_exponents(model.at(OMEGA), 2, method="dense", truncation="warn")
    assert forced.truncation > TRUNCATION_TOL
    assert forced.stable != reference.stable  # the verdict the indicator warned about is the wrong one


@pytest.mark.parametrize("method", ["dense", "sparse"])
def test_enough_harmonics_agree_with_the_monodromy(model, reference, method):
    with warnings.catch_warnings():
        warnings.simplefilter("error", TruncationWarning)
        hill = characteristic_exponents(model.at(OMEGA), 8, method=method)
    assert hill.truncation < TRUNCATION_TOL
    assert hill.stable == reference.stable
    assert np.log(hill.max_multiplier) == pytest.approx(np.log(reference.max_multiplier), abs=1e-7)


def test_truncation_choice_is_checked(model):
    with pytest.raises(InputError, match="truncation must be one of"):
        characteristic_exponents(model.at(OMEGA), 8, method="dense", truncation="ignore")


@pytest.mark.parametrize("stability", ["dense", "sparse", "hill"])
def test_a_sweep_flags_the_truncated_points(model, reference, stability):
    with pytest.warns(TruncationWarning, match="2 of 2 speeds failed"):
        batch = SpeedSolver(model, 2, stability=stability).solve_many([OMEGA, 2 * OMEGA])
    assert all("truncated" in m and "increase harmonics" in m for m in batch.message)
    assert not batch.stable.any() and np.isnan(batch.max_real).all()
    with warnings.catch_warnings():
        warnings.simplefilter("error", TruncationWarning)
        good = SpeedSolver(model, 8, stability=stability).solve_many([OMEGA, 2 * OMEGA])
    assert (good.message == "").all() and bool(good.stable[0]) == reference.stable


def test_a_sweep_records_the_truncated_point_as_failed(model):
    from periodyn.engine.front import sweep

    with pytest.warns(TruncationWarning):
        ds = sweep(model, np.array([OMEGA]), 2, stability="dense", progress=False)
    assert ds["status"].values[0] == STATUS_FAILED and "truncated" in str(ds["message"].values[0])


def test_solve_point_refuses_the_truncated_verdict_as_the_speed_solver_does(model):
    from periodyn.speeds import solve_point

    with pytest.raises(ConvergenceError, match="truncated"):
        solve_point(model.at(OMEGA), 2, stability="dense")
    with pytest.raises(ConvergenceError, match="truncated"), pytest.warns(TruncationWarning):
        SpeedSolver(model, 2, stability="dense").solve(OMEGA)
    assert not solve_point(model.at(OMEGA), 8, stability="dense").stable


def test_a_sweep_records_hill_truncation_per_point(model):
    from periodyn.engine.front import sweep

    speeds = np.array([OMEGA, 2 * OMEGA])
    ds = sweep(model, speeds, 8, stability="dense", progress=False)
    edge = ds["hill_truncation"].values
    scalar = [characteristic_exponents(model.at(w), 8, method="dense").truncation for w in speeds]
    assert np.all(edge <= TRUNCATION_TOL) and edge == pytest.approx(scalar, rel=1e-6, abs=1e-15)
    no_hill = sweep(model, speeds, 8, stability="magnus", progress=False)
    assert np.isnan(no_hill["hill_truncation"].values).all()
