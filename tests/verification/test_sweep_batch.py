"""The sweep's batched path (harmonic balance of a chunk of speeds, in half-period symmetry
classes where the model has them; vectorized amplitudes; columns filled as arrays) against
the per-point path (``solve_point`` on ``model.at(omega)``, one full HB solve per speed)."""

import numpy as np
import pytest

import periodyn
from periodyn.speeds import SpeedSolver, solve_point
import periodyn.harmonic.batch_balance as batch_module
from periodyn.harmonic.batch_balance import symmetry_classes
from periodyn.stability.magnus import half_period_signs


@pytest.fixture(scope="module")
def cardan():
    return periodyn.examples.cardan_shaft()


def test_cardan_balance_solves_one_half_size_class(cardan):
    """The Cardan shaft's coefficients repeat after half a turn up to the signs of its
    bending coordinates, so the real HB matrix decouples into two classes (their couplings
    are round-off of the full matrix); the forcing reaches one of them (the other's force
    harmonics are round-off), the only system solved, of about half the size."""
    solver = SpeedSolver(cardan, 12, stability=False)
    signs = half_period_signs(*cardan._power_spectra[:3])
    assert signs is not None and solver.batch_balance == "dense"
    a, b = symmetry_classes(12, cardan.n, signs)
    assert a.size + b.size == solver.pattern.size
    A = np.tensordot(500.0 ** np.arange(len(solver.harmonic.W)), solver.harmonic.real_balance_terms, 1)
    assert np.abs(A[np.ix_(a, b)]).max() <= 1e-12 * np.abs(A).max()
    (rows, _, _), = solver.balance.dense_blocks
    assert rows.size < 0.6 * solver.pattern.size
    forcing = np.abs(solver.harmonic.real_rhs).max(axis=0)
    other = np.setdiff1d(np.arange(solver.pattern.size), rows)
    assert forcing[other].max() <= 1e-12 * forcing.max() < forcing[rows].max()


def test_cardan_batched_equals_per_point(cardan):
    wb = cardan.metadata["omega_b"]
    speeds = np.array([0.05, 0.33, 0.5, 0.66, 0.87, 0.999]) * wb
    batch = SpeedSolver(cardan, 12, stability=False).solve_many(speeds)
    assert (batch.message == "").all()
    for i, w in enumerate(speeds):
        one = solve_point(cardan.at(w), 12, stability=False)
        scale = np.abs(one.output_harmonics).max()
        np.testing.assert_allclose(batch.output_harmonics[i], one.output_harmonics, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(batch.amplitude[i], one.amplitude, rtol=1e-12, atol=1e-14 * scale)
        np.testing.assert_allclose(batch.mean[i], one.mean, rtol=0, atol=1e-12 * scale)
        assert batch.residual[i] < 1e-13 and one.residual < 1e-13


def test_cardan_even_deflection_and_odd_twist_harmonics_vanish(cardan):
    """Schwab & Meijaard (2001), sec. 4.4: the even harmonics of the deflection and the odd
    harmonics of the twist vanish; the classes give them exactly zero."""
    wb = cardan.metadata["omega_b"]
    batch = SpeedSolver(cardan, 12, stability=False).solve_many(np.array([0.3, 0.7]) * wb)
    l = np.arange(-12, 13)
    names = cardan.output_names
    for i in range(2):
        for name, vanish in (("midpoint_deflection", l % 2 == 0), ("twist", l % 2 == 1)):
            y = batch.output_harmonics[i, :, names.index(name)]
            assert np.abs(y[vanish]).max() <= 1e-12 * np.abs(y).max()
            assert np.abs(y[~vanish]).max() > 0


def _forced_oscillator():
    """q'' + 0.1 q' + (1 + 0.3 cos 2 theta) q = cos theta: half-period signs (1,), forcing
    in the odd harmonics only."""
    p = 16
    theta = 2 * np.pi * np.arange(p) / p
    return periodyn.OmegaSplitModel.from_samples(np.ones((p, 1, 1)), [np.full((p, 1, 1), 0.1)],
                                                 [(1.0 + 0.3 * np.cos(2 * theta))[:, None, None]],
                                                 [np.cos(theta)[:, None]])


def test_unforced_class_is_zero_and_the_forced_one_matches_the_full_solve():
    model = _forced_oscillator()
    solver = SpeedSolver(model, 5, stability=False)
    m, n = 5, 1
    classes = symmetry_classes(m, n, solver.balance.signs)
    assert len(classes) == 2 and len(symmetry_classes(m, n, None)) == 1
    speeds = np.array([0.4, 0.9, 1.7])
    q, residual, message = solver.balance.solve_many(speeds, "dense")
    full, full_residual, _ = solver.balance.solve_many(speeds, None)  # one full solve per speed
    assert len(solver.balance.dense_blocks) == 1 and (message == "").all()
    np.testing.assert_allclose(q, full, rtol=0, atol=1e-14 * np.abs(full).max())
    assert (q[:, 1::2] == 0).all() and np.abs(q[:, ::2]).max() > 0  # index l + 5: even l unforced, zero
    np.testing.assert_array_less(residual, 1e-14)


@pytest.mark.parametrize("stability", [False, "dense"])
def test_sweep_equals_the_point_by_point_sweep(cardan, stability):
    """periodyn.sweep of the OmegaSplitModel (chunks of speeds, batched) against the same
    sweep through a callable model, which goes speed by speed through solve_point."""
    wb = cardan.metadata["omega_b"]
    speeds = np.linspace(0.2, 0.95, 7) * wb
    fast = periodyn.sweep(cardan, speeds, 8, stability=stability, progress=False)
    slow = periodyn.sweep(cardan.at, speeds, 8, stability=stability, progress=False)
    scale = np.abs(slow["harmonics"].values).max()
    np.testing.assert_allclose(fast["harmonics"].values, slow["harmonics"].values, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(fast["amplitude"].values, slow["amplitude"].values, rtol=1e-12)
    np.testing.assert_array_equal(fast["status"].values, slow["status"].values)
    np.testing.assert_array_equal(fast["stable"].values, slow["stable"].values)
    if stability:
        np.testing.assert_allclose(fast["max_real_exponent"].values, slow["max_real_exponent"].values, rtol=0,
                                   atol=1e-9)


def test_iterative_balance_equals_direct_lu(monkeypatch):
    """GMRES preconditioned with the LU at an earlier speed (the large-system HB path, here
    at the slider-crank's size N = 100) against the stacked direct solve, over 150-300
    rad/s through the resonances: the same harmonics to the GMRES tolerance amplified by
    the condition, residuals <= 1e-12, and most speeds solved without an LU of their own;
    where single precision cannot hold the matrix, the double-precision LU of every speed."""
    model = periodyn.examples.slider_crank(damping=0.02)
    speeds = np.linspace(150.0, 300.0, 61)
    direct = SpeedSolver(model, 12, stability=False)
    assert direct.batch_balance == "dense" and direct.pattern.size < batch_module.ITERATIVE_MIN
    reference = direct.solve_many(speeds)
    monkeypatch.setattr(batch_module, "ITERATIVE_MIN", 1)
    solver = SpeedSolver(model, 12, stability=False)
    iterative = np.concatenate([solver.solve_many(speeds[i: i + 4]).output_harmonics for i in range(0, 61, 4)])
    assert 1 <= solver.balance.factorizations <= speeds.size // 3
    scale = np.abs(reference.output_harmonics).max(axis=(1, 2), keepdims=True)
    assert np.abs(iterative - reference.output_harmonics).max() / scale.min() < 1e-10
    assert (solver.solve_many(speeds).residual <= 1.01 * batch_module.GMRES_RTOL).all()
    monkeypatch.setattr(batch_module, "SINGLE_MAX", 0.0)  # entries beyond single precision: double LU per speed
    fallback = SpeedSolver(model, 12, stability=False)
    direct = fallback.solve_many(speeds)
    assert fallback.balance.factorizations == speeds.size and direct.residual.max() < 1e-14
    np.testing.assert_allclose(direct.output_harmonics, reference.output_harmonics, rtol=0, atol=1e-13 * scale.min())
