"""Continuation results: Branch <-> netCDF round trip, options object, special points with their orbits."""

import numpy as np
import pytest

import periodyn
from periodyn.arclength import Branch, ContinuationOptions, continuation, load_branch
from periodyn.errors import InputError
from periodyn.examples.dae_examples import duffing, inverted_pendulum


@pytest.fixture(scope="module")
def duffing_branch():
    return continuation(duffing(0.05, 1.0, 0.1), (0.9, 1.5), harmonics=7, options=ContinuationOptions(ds_max=0.1))


def test_options_object_and_keywords_are_the_same_and_unknown_keywords_are_refused(duffing_branch):
    kw = continuation(duffing(0.05, 1.0, 0.1), (0.9, 1.5), harmonics=7, ds_max=0.1)
    np.testing.assert_array_equal(kw.omega, duffing_branch.omega)
    with pytest.raises(InputError, match="unknown continuation option"):
        continuation(duffing(), (0.9, 1.5), harmonics=7, dsmax=0.1)
    with pytest.raises(InputError):
        ContinuationOptions(ds_min=1.0, ds_max=0.1)
    with pytest.raises(InputError, match="stability"):
        ContinuationOptions(stability="eigen")


def test_special_points_carry_their_solution(duffing_branch):
    br = duffing_branch
    assert isinstance(br, periodyn.Branch) and len(br.points("fold")) == 2
    for sp in br.points("fold"):
        sol = sp.solution
        assert sol.residual <= 1e-8 and sol.omega == sp.omega
        np.testing.assert_allclose(sp.amplitude, sol.amplitude(), rtol=0, atol=0)
        # at the fold located from dp/ds = 0, the Floquet path (Magnus) gives a multiplier +1: measured 7e-8
        assert np.min(np.abs(sp.multipliers - 1.0)) < 1e-6
        # test function dp/ds: opposite signs at the bracket, ~0 at the fold
        assert sp.test_values[0] * sp.test_values[1] < 0 and abs(sp.test_values[2]) < 1e-9
        # the critical eigenvector is the unit null vector of the IHB Jacobian there
        J = br.problem.residual_jacobian(br.problem.from_solution(sol), sp.omega, sol.parameters)[1]
        J = J.toarray() if hasattr(J, "toarray") else J
        assert np.linalg.norm(J @ sp.eigenvector) < 1e-6 * np.linalg.norm(J, 2)
        # the fold is the extreme of omega between its two neighbours
        near = br.omega[sp.index: sp.index + 2]
        assert sp.omega >= near.max() - 1e-12 or sp.omega <= near.min() + 1e-12


def _same(a: Branch, b: Branch):
    for name in ("omega", "parameter", "amplitude", "max_multiplier", "residual", "iterations"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert a.stable.tolist() == b.stable.tolist() and a.status == b.status and a.parameter_name == b.parameter_name
    for x, y in zip(a.solutions, b.solutions):
        np.testing.assert_array_equal(x.harmonics, y.harmonics)
        np.testing.assert_array_equal(x.lambda_harmonics, y.lambda_harmonics)
        np.testing.assert_allclose(x.multipliers, y.multipliers, rtol=1e-13)
        assert x.subharmonic == y.subharmonic and x.method == y.method and x.stable == y.stable
    assert len(a.special_points) == len(b.special_points)
    for p, q in zip(a.special_points, b.special_points):
        assert (p.type, p.index, p.omega, p.parameter) == (q.type, q.index, q.omega, q.parameter)
        np.testing.assert_array_equal(p.amplitude, q.amplitude)
        np.testing.assert_array_equal(p.solution.harmonics, q.solution.harmonics)
        np.testing.assert_allclose(p.multipliers, q.multipliers, rtol=1e-13)
        assert p.multiplier == q.multiplier or (np.isnan(p.multiplier) and np.isnan(q.multiplier))
        np.testing.assert_array_equal(p.test_values, q.test_values)
        assert (p.eigenvector is None) == (q.eigenvector is None)
        if p.eigenvector is not None:
            np.testing.assert_array_equal(p.eigenvector, q.eigenvector)


def test_branch_round_trips_through_netcdf(duffing_branch, tmp_path):
    path = duffing_branch.save(tmp_path / "duffing.nc")
    back = load_branch(path)
    _same(duffing_branch, back)
    assert back.options["ds_max"] == 0.1 and back.problem is None


def test_dae_branch_with_constraint_forces_and_period_doubling_round_trips(tmp_path):
    br = continuation(inverted_pendulum(), (8.8, 9.4), harmonics=6, ds_max=0.1)
    assert len(br.points("period-doubling")) == 1
    ds = br.to_dataset()
    assert ds["lambda_harmonics"].shape[1:] == (13, 2) and ds["stable"].dtype == np.int8
    _same(br, load_branch(br.save(tmp_path / "inverted.nc")))


def test_branch_without_stability_round_trips(tmp_path):
    br = continuation(duffing(), (0.5, 0.7), harmonics=2, stability=None, max_points=5)
    assert all(s is None for s in br.stable)
    back = load_branch(br.save(tmp_path / "plain.nc"))
    assert all(s is None for s in back.stable) and np.all(np.isnan(back.max_multiplier))
    np.testing.assert_array_equal(back.amplitude, br.amplitude)
