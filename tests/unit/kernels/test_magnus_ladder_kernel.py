"""The jitted Magnus-ladder kernels (periodyn.kernels.solvers.magnus_ladder) against plain-NumPy
twins, and the ladder's per-speed independence."""

import numpy as np
import pytest

import periodyn
from periodyn.kernels.solvers import magnus_ladder as kernel
from periodyn.kernels.solvers.floquet import magnus_monodromies
from periodyn.stability.magnus import ERROR_FLOOR, MagnusLadder, gauss_angles
from periodyn.numerics.spectra import StackedSpectra, real_basis


def balanced_terms_twin(mass, damping, stiffness):
    """Plain NumPy: A = sum_p omega^p terms[p] for y = (a q, q')."""
    g, n = mass.shape[:2]
    Pc, Pk = damping.shape[-1], stiffness.shape[-1]
    MinvC = np.linalg.solve(mass[:, None], np.moveaxis(damping, -1, 1))  # (g, Pc, n, n)
    MinvK = np.linalg.solve(mass[:, None], np.moveaxis(stiffness, -1, 1))
    top = np.abs(MinvK[:, 0]).sum(axis=2).max()
    a = np.sqrt(top) if top > 0 else 1.0
    terms = np.zeros((max(Pc, Pk), g, 2 * n, 2 * n))
    terms[0, :, :n, n:] = a * np.eye(n)
    terms[:Pk, :, n:, :n] = -np.moveaxis(MinvK, 1, 0) / a
    terms[:Pc, :, n:, n:] = -np.moveaxis(MinvC, 1, 0)
    return terms, a


def moduli_twin(terms, omega, points, signs):
    """Plain NumPy exponents (sorted by real, then imaginary part) and sorted moduli."""
    d = terms.shape[-1]
    Phi = np.empty((1, d, d))
    w = omega if signs is None else 2 * omega
    magnus_monodromies(terms, np.array([w]), Phi, points)
    Phi = Phi[0]
    if signs is not None:
        Phi = np.concatenate([signs, signs])[:, None] * Phi
        Phi = Phi @ Phi
    lam = np.log(np.linalg.eigvals(Phi)) * omega / (2 * np.pi)
    lam = lam[np.lexsort((lam.imag, lam.real))]
    return lam, np.sort(np.exp(lam.real * 2 * np.pi / omega))


def _spectra(model):
    return model._power_spectra[:3]


@pytest.fixture(scope="module")
def crank():
    return periodyn.examples.slider_crank(damping=0.02, samples=32)


def test_balanced_terms_equal_the_numpy_twin(crank):
    rng = np.random.default_rng(3)
    g, n = 5, 4
    mass = rng.standard_normal((g, n, n)) + 4 * np.eye(n)
    damping, stiffness = rng.standard_normal((g, n, n, 2)), rng.standard_normal((g, n, n, 3))
    got, a = kernel.balanced_terms(mass, damping, stiffness, 0.0)
    want, b = balanced_terms_twin(mass, damping, stiffness)
    assert a == pytest.approx(b, rel=1e-14)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-13 * np.abs(want).max())


def test_singular_mass_gives_nan_terms_not_an_exception():
    mass = np.zeros((2, 2, 2))
    terms, _ = kernel.balanced_terms(mass, np.ones((2, 2, 2, 1)), np.ones((2, 2, 2, 1)), 0.0)
    assert np.isnan(terms[:, :, 2:]).all()


@pytest.mark.parametrize("points", [2, 3])
@pytest.mark.parametrize("halve", [False, True])
def test_rung_terms_equal_basis_product_and_twin(crank, points, halve):
    stacked = StackedSpectra(*_spectra(crank))
    span, steps = (np.pi if halve else 2 * np.pi), 8
    values = real_basis(stacked.harmonics, gauss_angles(steps, 0.0, span, points)) @ stacked.rows
    want, b = balanced_terms_twin(*stacked.split(values))
    if halve:
        want = want / (2.0 ** np.arange(want.shape[0]))[:, None, None, None]
    Pc, Pk = (X.shape[-1] for X in _spectra(crank)[1:])
    rows = np.ascontiguousarray(stacked.rows)
    got, a = kernel.rung_terms(rows, crank.n, Pc, Pk, steps, points, span, halve, 0, steps, 0.0)
    assert a == pytest.approx(b, rel=1e-12)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max())
    # a block of the steps with a given balancing scale: those steps' Gauss points, rescaled
    block, _ = kernel.rung_terms(rows, crank.n, Pc, Pk, steps, points, span, halve, 3, 4, 2 * b)
    D = np.diag(np.r_[np.full(crank.n, 2.0), np.ones(crank.n)])  # y = (2 a q, q') instead of (a q, q')
    np.testing.assert_allclose(block, D @ want[:, 3 * points: 7 * points] @ np.linalg.inv(D), rtol=0,
                               atol=1e-12 * np.abs(want).max())


@pytest.mark.parametrize("builder", [lambda: periodyn.examples.slider_crank(damping=0.02, samples=32),
                                     lambda: periodyn.examples.cardan_shaft(samples=32)])
def test_rung_moduli_equal_the_numpy_twin(builder):
    model = builder()
    ladder = MagnusLadder(*_spectra(model))
    for order, steps, w in ((4, 64, 220.0), (6, 32, 300.0)):
        exps, mod = ladder._moduli(np.array([w]), steps, order)
        lam, want = moduli_twin(ladder.terms(steps, order)[0], w, order // 2, ladder.signs)
        np.testing.assert_allclose(mod[0], want, rtol=0, atol=1e-14 * want.max())
        np.testing.assert_allclose(exps[0], lam, rtol=0, atol=1e-14 * np.abs(lam).max())  # same values, same order


@pytest.mark.parametrize("builder", [lambda: periodyn.examples.slider_crank(damping=0.02, samples=32),
                                     lambda: periodyn.examples.cardan_shaft(samples=32)])
def test_streamed_rung_equals_the_kept_rung(builder):
    """A rung whose terms are built block by block (blocks of 8 and 24 of 64 steps, the
    ladder's balancing scale) gives the kept rung's multiplier moduli to round-off of the
    largest (the most damped modes' multipliers, near 1e-17 of it, are round-off)."""
    model = builder()
    ladder = MagnusLadder(*_spectra(model))
    d = 2 * model.n
    for order, w in ((4, 220.0), (6, 300.0)):
        _, want = ladder._moduli(np.array([w]), 64, order)
        for block in (8, 24):
            exps, mod, Phi = np.empty(d, complex), np.empty(d), np.empty((d, d))
            kernel.streamed_moduli(ladder._rows, model.n, *ladder.powers, 64, order // 2, ladder.span, ladder.scale,
                                   block, w, ladder._signs(), Phi, exps, mod)
            np.testing.assert_allclose(mod, want[0], rtol=0, atol=1e-12 * want.max())


def test_rungs_beyond_the_kept_terms_climb_streamed():
    """With room for the terms of 16 steps only, the ladder still climbs to its rungs of
    32-128 steps (built block by block) and gives the same steps, verdicts and exponents."""
    model = periodyn.examples.slider_crank(damping=0.02, samples=32)
    speeds = np.array([150.0, 230.0, 300.0])
    full = MagnusLadder(*_spectra(model))
    small = MagnusLadder(*_spectra(model))
    small.TERMS_ENTRIES = 16 * 3 * (2 * model.n) ** 2 * max(small.powers)
    assert small.kept_steps(6) == 16 and small.kept_steps(4) == 16
    want, got = full.solve(speeds, np.inf), small.solve(speeds, np.inf)
    assert (got.steps > 16).all() and got.accepted.all()
    np.testing.assert_array_equal(got.steps, want.steps)
    moduli = [np.sort(np.exp(e.exponents.real * (2 * np.pi / speeds)[:, None])) for e in (got, want)]
    np.testing.assert_allclose(moduli[0], moduli[1], rtol=0, atol=1e-12 * moduli[1].max())


def test_speeds_in_the_erratic_regime_need_two_comparisons(crank):
    """A speed whose first rung stays at FIRST_MAX (here every speed: no halving, and the
    generator asks for more steps) is certified only by two successive comparisons, and
    claims the larger of their estimates."""
    ladder = MagnusLadder(*_spectra(crank))
    ladder.FIRST_RHO, ladder.CLEAN_RHO = 0.5, 0.0
    w = np.array([230.0])
    assert ladder.first_rungs(w, 4)[0] == ladder.FIRST_MAX == 128
    est = ladder.solve(w, np.inf)
    assert est.accepted[0] and est.order[0] == 4 and est.steps[0] == 512
    mods = {N: ladder._moduli(w, N, 4)[1][0] for N in (128, 256, 512)}

    def estimate(coarse, fine):
        a, b = mods[coarse], mods[fine]
        return max(abs(np.log(b[-1] / a[-1])), np.abs(b - a).max() / b[-1], ERROR_FLOOR)

    assert est.error[0] == pytest.approx(max(estimate(128, 256), estimate(256, 512)), rel=1e-9)


def test_each_speed_climbs_alone(crank):
    """A speed's rungs, verdict and exponents do not depend on the other speeds of the
    call (speeds starting at different first rungs are climbed in one call)."""
    ladder = MagnusLadder(*_spectra(crank))
    speeds = np.linspace(20.0, 320.0, 40)
    assert np.unique(ladder._plan(speeds)[1]).size > 1  # several first rungs in the call
    together = ladder.solve(speeds, np.full(speeds.size, 0.05))
    for i in (0, 12, 25, 39):
        alone = MagnusLadder(*_spectra(crank)).solve(speeds[i:i + 1], np.array([0.05]))
        assert alone.steps[0] == together.steps[i] and alone.accepted[0] == together.accepted[i]
        np.testing.assert_array_equal(alone.exponents[0], together.exponents[i])


def test_cost_and_first_rungs_follow_the_model(crank):
    ladder = MagnusLadder(*_spectra(crank))
    w = np.array([50.0, 200.0])
    cost = ladder.cost(w, 64, 4)
    assert cost[0] > cost[1] > 0  # slower speeds: larger generators, more squarings
    first = ladder.first_rungs(w, 6)
    assert (first >= MagnusLadder.START[6] // 2).all() and (first & (first - 1) == 0).all()
    order, first_plan, first_cost = ladder._plan(w)
    np.testing.assert_allclose(first_cost, [ladder.cost(w[i:i + 1], first_plan[i], order[i])[0]
                                            + ladder.cost(w[i:i + 1], 2 * first_plan[i], order[i])[0]
                                            for i in range(2)])
