"""Arc-length continuation: Duffing folds (analytic HB1, shooting), period doubling, parameter curves."""

import numpy as np
import pytest
from scipy.optimize import fsolve

from periodyn.arclength import continuation, switch_period_doubling
from periodyn.nonlinear import ihb
from periodyn.examples.dae_examples import duffing, inverted_pendulum, rod_pendulum
from periodyn.examples.pendulum_equation import pendulum_nonlinear
from periodyn.nonlinear import shooting

ZETA, ALPHA, F = 0.05, 1.0, 0.1


def hb1_folds():
    """Folds of the single-harmonic Duffing balance G(A, w) = ((k - w^2)^2 + (2 zeta w)^2) A^2 - F^2,
    k = 1 + 3 alpha A^2 / 4: solve G = dG/dA = 0 (the classical analytic estimate)."""
    def eqs(v):
        A, w = v
        k = 1 + 0.75 * ALPHA * A * A
        G = ((k - w * w) ** 2 + (2 * ZETA * w) ** 2) * A * A - F * F
        GA = 2 * A * ((k - w * w) ** 2 + (2 * ZETA * w) ** 2) + A * A * 2 * (k - w * w) * 1.5 * ALPHA * A
        return [G, GA]
    return sorted(fsolve(eqs, guess, xtol=1e-12)[1] for guess in ([0.8, 1.23], [0.25, 1.16]))


@pytest.fixture(scope="module")
def duffing_branch():
    return continuation(duffing(ZETA, ALPHA, F), (0.6, 1.8), harmonics=7)


def test_hb1_continuation_reproduces_analytic_folds():
    br = continuation(duffing(ZETA, ALPHA, F), (0.6, 1.8), harmonics=1, ds_max=0.1)
    folds = sorted(p.omega for p in br.points("fold"))
    assert len(folds) == 2
    np.testing.assert_allclose(folds, hb1_folds(), rtol=1e-8)


def test_duffing_folds_and_unstable_middle_branch_match_shooting(duffing_branch):
    br = duffing_branch
    assert br.status == "parameter range covered"
    assert np.all(br.residual <= 1e-8) and br.iterations.max() <= 8
    folds = br.points("fold")
    assert len(folds) == 2
    lo, hi = sorted(p.omega for p in folds)
    # shooting continuation over the fold region finds the same folds
    sh = continuation(duffing(ZETA, ALPHA, F), (1.1, 1.3), harmonics=7, method="shooting", ds_max=0.2)
    sh_folds = sorted(p.omega for p in sh.points("fold"))
    np.testing.assert_allclose(sh_folds, [lo, hi], rtol=1e-7)
    # the middle branch between the folds is unstable, the outer ones stable
    i1, i2 = sorted(p.index for p in folds)
    assert not np.any(br.stable[i1 + 2:i2 - 1])
    assert np.all(br.stable[: i1 - 1]) and np.all(br.stable[i2 + 2:])
    # a middle-branch point: IHB multipliers equal the shooting (direct integration) ones
    mid = br.solutions[(i1 + i2) // 2]
    direct = shooting(duffing(ZETA, ALPHA, F), mid.omega, initial=mid)
    assert np.abs(direct(np.linspace(0, 5, 9)) - mid(np.linspace(0, 5, 9))).max() < 1e-7
    np.testing.assert_allclose(np.sort(np.abs(mid.multipliers)), np.sort(np.abs(direct.multipliers)), rtol=1e-6)
    assert mid.max_multiplier > 1.0 and direct.stable is False


def test_parameter_continuation_in_forcing_amplitude():
    s = rod_pendulum()
    br = continuation(s, 3.6, harmonics=8, parameter=("f", 0.02, 0.3), stability=None)
    assert br.parameter_name == "f" and np.all(br.omega == 3.6)
    assert br.parameter[-1] >= 0.3 and np.all(br.residual <= 1e-8)
    k = len(br) // 2
    direct = ihb(s.with_parameters(f=br.parameter[k]), 3.6, 8, initial=br.solutions[k], stability=None)
    np.testing.assert_allclose(br.amplitude[k], direct.amplitude(), atol=1e-9)
    # amplitude grows monotonically with the forcing away from the fold-free range
    assert np.all(np.diff(br.amplitude[:, 2]) > 0)


@pytest.fixture(scope="module")
def inverted_branch():
    return continuation(inverted_pendulum(), (6.0, 14.0), harmonics=8, ds_max=0.1)


def test_inverted_pendulum_period_doubling_detected_and_followed(inverted_branch):
    br = inverted_branch
    pd = br.points("period-doubling")
    assert len(pd) == 2  # the T-orbit is unstable between two period-doubling points
    lo, hi = sorted(p.omega for p in pd)
    assert 8.5 < lo < 9.5 and 11.5 < hi < 12.5
    for p in pd:
        assert abs(p.multiplier + 1) < 1e-6
    inside = (br.omega > lo + 0.05) & (br.omega < hi - 0.05)
    outside = (br.omega < lo - 0.05) | (br.omega > hi + 0.05)
    assert not np.any(br.stable[inside]) and np.all(br.stable[outside])
    # the unstable T-orbit inside: shooting (direct integration) gives a multiplier below -1 too
    k = int(np.argmax(inside))
    direct = shooting(inverted_pendulum(), br.omega[k], initial=br.solutions[k])
    mu = direct.multipliers[np.argmax(np.abs(direct.multipliers))]
    assert mu.real < -1 and abs(mu.imag) < 1e-8
    np.testing.assert_allclose(abs(mu), br.max_multiplier[k], rtol=1e-6)


def test_period_doubled_branch_is_a_2T_orbit_confirmed_by_shooting(inverted_branch):
    br = inverted_branch
    pd = min(br.points("period-doubling"), key=lambda p: p.omega)
    b2 = switch_period_doubling(br, pd, 14.0, max_points=12)
    assert np.all(b2.residual <= 1e-8) and len(b2) == 12
    sol = b2.solutions[-1]
    H2 = (sol.harmonics.shape[0] - 1) // 2
    odd = np.abs(sol.harmonics[H2 + 1::2]).max()
    assert sol.subharmonic == 2 and odd > 1e-3  # genuine subharmonic content
    direct = shooting(inverted_pendulum(), sol.omega, initial=sol, subharmonic=2)
    t = np.linspace(0, sol.period, 17)
    assert np.abs(direct(t) - sol(t)).max() < 1e-6
    np.testing.assert_allclose(np.sort(np.abs(sol.multipliers)), np.sort(np.abs(direct.multipliers)), rtol=1e-5)


def test_oversized_steps_are_recovered_and_give_the_same_folds():
    """ds = 1 forces rejected steps (corrector failure or tangent turn) and halving; the
    branch still covers the range and the refined folds equal those of a fine run."""
    coarse = continuation(duffing(ZETA, ALPHA, F), (0.6, 1.8), harmonics=3, ds=1.0, ds_max=1.0, stability=None)
    fine = continuation(duffing(ZETA, ALPHA, F), (0.6, 1.8), harmonics=3, ds_max=0.05, stability=None)
    assert coarse.status == "parameter range covered" and len(coarse) < len(fine) / 2
    np.testing.assert_allclose(sorted(p.omega for p in coarse.points("fold")),
                               sorted(p.omega for p in fine.points("fold")), rtol=1e-8)
    assert np.all(coarse.residual <= 1e-8)


def test_nonlinear_elliptic_pendulum_branch_reaches_the_end_with_defaults():
    """Eq. (28) over 0.1-1.4 omega0 in one call with default options: the first orbit is tiny
    (amplitude 2.5e-3 rad), the resonance near omega0/2 swings 2 rad; the step scale grows
    with the branch, so the end is reached in far fewer than 1,000 points."""
    w0 = np.sqrt(9.81)
    br = continuation(pendulum_nonlinear(), (0.1 * w0, 1.4 * w0))
    assert br.status == "parameter range covered" and br.omega[-1] >= 1.4 * w0
    assert len(br) < 1000 and br.amplitude.max() > 1.0
    assert np.all(br.residual <= 1e-8)
    # the resonance near omega0/2 bends over: a pair of folds around it
    assert sum(0.45 * w0 < p.omega < 0.95 * w0 for p in br.points("fold")) == 2


def test_a_branch_ended_early_says_why_and_which_option_to_change():
    br = continuation(duffing(ZETA, ALPHA, F), (0.6, 1.8), harmonics=3, max_points=6)
    assert br.status.startswith("max_points reached") and "raise max_points" in br.status and len(br) == 6
