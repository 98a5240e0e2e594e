"""Reduced harmonic balance (periodyn.harmonic.reduced_balance) against the full HB solve."""

import numpy as np
import pytest

import periodyn.harmonic.reduced_balance as reduced_balance
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
from periodyn.harmonic.batch_balance import BalanceBatch
from periodyn.harmonic.operator import HarmonicOperator
from periodyn.harmonic.reduced_balance import RTOL, ReducedBalance
from periodyn.harmonic.truncation import above_noise
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
    """The residual evaluated on 2m + band + 1 angles, plus the bound of what the mass's
    harmonics leave out (taken by its mean: MEAN_ONLY), bounds |f - W q| / |f| of the block
    operator (its own matrix-vector product) and exceeds it by at most twice that bound, so
    the certificate is the full equations'."""
    model, op, full, rb = case
    above = above_noise(rb.mags, rb.floors, rb.exponents, SPEEDS).any(axis=0)
    assert np.array_equal(np.flatnonzero(above & rb.mean_only), [0])  # of the terms above noise, the mass
    q, rel, _ = rb.solve_many(SPEEDS, 4)
    left = rb.left_out(SPEEDS, q[:, M:]) / np.linalg.norm(rb.forcing(SPEEDS).reshape(len(SPEEDS), -1), axis=1)
    assert np.all(left < 0.1 * RTOL)
    for i, w in enumerate(SPEEDS):
        hill = op.at(w)
        direct = np.linalg.norm(hill.rhs - op.pattern.apply(hill.blocks[0], q[i].reshape(-1)))
        direct /= np.linalg.norm(hill.rhs)
        assert direct <= rel[i] * (1 + 1e-3) and rel[i] <= direct * (1 + 1e-3) + 2 * left[i]


def test_the_left_out_bound_holds_the_mass_harmonics(case):
    """left_out bounds the mass harmonics' action sum_(d != 0) M_d (q'')_(a-d) (a = -m..m,
    |d| <= band), here computed by the harmonic convolution of the model's own spectrum."""
    model, op, full, rb = case
    band, K = op.pattern.band, (model._power_spectra[0].shape[0] - 1) // 2
    Ms = model._power_spectra[0]
    b = np.arange(-M, M + 1)
    rng = np.random.default_rng(3)
    for i, w in enumerate(SPEEDS):
        for q in (full[i], full[i] * np.exp(1j * rng.uniform(0, 2 * np.pi, full[i].shape))):
            q = 0.5 * (q + np.conj(q[::-1]))  # a real signal
            acc = -(b * w)[:, None] ** 2 * q
            exact = np.zeros_like(q)
            for a in range(-M, M + 1):
                for j in range(-M, M + 1):
                    if 0 < abs(a - j) <= band:
                        exact[a + M] += Ms[K + a - j] @ acc[j + M]
            bound = rb.left_out(np.array([w]), q[None, M:])[0]
            assert np.linalg.norm(exact) <= bound and np.linalg.norm(exact) > 0


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
    """With all modes the kept solve is the full one: its residual is round-off plus what the
    mass's harmonics leave out of the computed one, and the reported one adds their bound
    (:meth:`ReducedBalance.left_out`)."""
    model, op, full, rb = case
    q, rel, steps = rb.solve_many(SPEEDS, model.n)
    left = rb.left_out(SPEEDS, q[:, M:]) / np.linalg.norm(rb.forcing(SPEEDS).reshape(len(SPEEDS), -1), axis=1)
    assert np.all(steps == 1) and np.all(rel < 1e-13 + 2 * left)
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
