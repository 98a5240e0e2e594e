"""Reduced harmonic balance (periodyn.harmonic.reduced_balance) against the full HB solve."""

import numpy as np
import pytest

import periodyn.harmonic.reduced_balance as reduced_balance
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
from periodyn.harmonic.batch_balance import BalanceBatch
from periodyn.harmonic.operator import HarmonicOperator
from periodyn.harmonic.reduced_balance import RTOL, ReducedBalance
from periodyn.model.linearization import omega_split
from periodyn.model.reduce import mean_modes
from periodyn.speeds import SpeedSolver

M = 12
SPEEDS = np.array([150.0, 205.0, 266.0, 300.0])


def crank(elements: int):
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=elements))
    return omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=elements), 64)


@pytest.fixture(scope="module", params=[8, 16])
def case(request):
    model = crank(request.param)
    op = HarmonicOperator.for_model(model, M)
    full, residual, message = BalanceBatch(op).solve_many(SPEEDS, "dense")
    assert (message == "").all() and residual.max() < 1e-12
    return model, op, full, ReducedBalance(model, M, op.pattern.band, mean_modes(model))


def _relative(q, full):
    return (np.abs(q - full).reshape(len(q), -1).max(axis=1) / np.abs(full).reshape(len(q), -1).max(axis=1))


@pytest.mark.parametrize("k", [4, 8])
def test_reduced_balance_meets_the_full_solve(case, k):
    """With 4 or 8 of 16-32 modes the iteration reaches the full HB residual RTOL = 1e-10 in a
    few steps; the harmonics then agree with the dense LU solve to 1e-8 of the largest
    (the HB matrix amplifies the residual by at most ~1e2 here: observed 1e-11..1e-10)."""
    model, op, full, rb = case
    q, rel, steps = rb.solve_many(SPEEDS, k)
    assert np.all((steps > 0) & (steps <= reduced_balance.ITERATIONS)) and np.all(rel <= RTOL)
    assert _relative(q, full).max() <= 1e-8


def test_the_reported_residual_is_the_full_operators(case):
    """The residual evaluated on 2m + band + 1 angles equals |f - W q| / |f| of the block
    operator (its own matrix-vector product), so the certificate is the full equations'."""
    model, op, full, rb = case
    q, rel, _ = rb.solve_many(SPEEDS, 4)
    for i, w in enumerate(SPEEDS):
        hill = op.at(w)
        direct = np.linalg.norm(hill.rhs - op.pattern.apply(hill.blocks[0], q[i].reshape(-1)))
        direct /= np.linalg.norm(hill.rhs)
        assert direct == pytest.approx(rel[i], rel=1e-3, abs=1e-14)


def test_the_kept_modes_coupling_is_the_full_operators(case):
    """coupling(w, y) = Phi^T W Phi_l y of the block operator (its own matrix-vector product
    on the physical harmonics Phi_l y), harmonics a = 0..m."""
    model, op, full, rb = case
    k, Phi = 4, rb.modes.shapes
    y = np.random.default_rng(1).standard_normal((len(SPEEDS), M + 1, k, 2)) @ np.array([1.0, 1j])
    y[:, 0] = y[:, 0].real
    got = rb.coupling(SPEEDS, y, rb.coupling_terms(SPEEDS, k, rb.terms_at(SPEEDS)))
    for i, w in enumerate(SPEEDS):
        q = np.concatenate([np.conj(y[i, :0:-1]), y[i]]) @ Phi[:, :k].T  # (2m+1, n)
        direct = op.pattern.apply(op.at(w).blocks[0], q.reshape(-1)).reshape(2 * M + 1, -1)[M:] @ Phi
        assert np.abs(got[i] - direct).max() <= 1e-12 * np.abs(direct).max()


def test_all_modes_reproduce_the_full_solve_in_one_step(case):
    model, op, full, rb = case
    q, rel, steps = rb.solve_many(SPEEDS, model.n)
    assert np.all(steps == 1) and rel.max() < 1e-13
    assert _relative(q, full).max() < 1e-12


def test_a_speed_that_does_not_converge_is_reported(case, monkeypatch):
    model, op, full, rb = case
    monkeypatch.setattr(reduced_balance, "ITERATIONS", 1)
    _, rel, steps = rb.solve_many(SPEEDS, 4)
    assert np.all(steps == 0) and np.all(rel > RTOL)


def test_a_reduced_sweep_solves_the_reduced_balance_and_falls_back_in_full(monkeypatch):
    """stability="reduced" solves the reduced HB (balance_modes > 0, certified residual); the
    outputs equal those of the full HB; where the iteration does not converge the speed is
    solved in full (balance_modes 0) with the same outputs."""
    model = crank(8)
    reduced = SpeedSolver(model, M, stability="reduced").solve_many(SPEEDS)
    full = SpeedSolver(model, M, stability=False).solve_many(SPEEDS)
    assert np.all(reduced.message == "") and np.all(reduced.balance_modes > 0) and np.all(full.balance_modes == 0)
    assert np.all(reduced.residual <= RTOL)
    assert _relative(reduced.output_harmonics, full.output_harmonics).max() <= 1e-8
    monkeypatch.setattr(reduced_balance, "ITERATIONS", 1)
    fallback = SpeedSolver(model, M, stability="reduced").solve_many(SPEEDS)
    assert np.all(fallback.balance_modes == 0) and np.all(fallback.message == "")
    assert _relative(fallback.output_harmonics, full.output_harmonics).max() <= 1e-12
