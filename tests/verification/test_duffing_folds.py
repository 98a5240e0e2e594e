"""NLvib's Duffing example 01 (x'' + 0.05 x' + x + 0.1 x^3 = 0.18 cos(w t)) at continuation's
default options: folds against shooting continuation (direct integration), and the step
control placing points at the folds."""

import numpy as np
import pytest

from periodyn import DAE
from periodyn.arclength import continuation
from periodyn.examples.dae_examples import duffing


def nlvib_duffing():
    """The same oscillator as a vectorized user DAE (force over all samples in one call)."""
    def force(q, qd, t, w):
        return -0.05 * qd - q - 0.1 * q ** 3 + 0.18 * np.cos(w * t)[:, None]

    return DAE(np.eye(1), force, vectorized=True)


@pytest.fixture(scope="module")
def default_branch():
    return continuation(nlvib_duffing(), (0.5, 1.6))


def test_default_folds_match_shooting_continuation(default_branch):
    br = default_branch
    assert br.status == "parameter range covered" and np.all(br.residual <= 1e-8)
    folds = sorted(p.omega for p in br.points("fold"))
    assert len(folds) == 2
    # shooting (one period of DOP853 with the variational equations per Newton step) over the fold region
    sh = continuation(duffing(0.025, 0.1, 0.18), (1.05, 1.35), harmonics=7, method="shooting")
    ref = sorted(p.omega for p in sh.points("fold"))
    assert len(ref) == 2
    # measured: |difference| 1.2e-9 (H = 5 chosen by the default defect rule) and 3e-12 at H = 7
    np.testing.assert_allclose(folds, ref, rtol=0, atol=1e-6)
    # the stability verdict flips at the folds: unstable only on the middle branch
    i1, i2 = sorted(p.index for p in br.points("fold"))
    assert not np.any(br.stable[i1 + 2:i2 - 1]) and np.all(br.stable[:i1 - 1]) and np.all(br.stable[i2 + 2:])


def test_steps_shorten_at_the_folds_only(default_branch):
    """The tangent-turn step control: the points bracketing each fold lie far closer together
    (in omega) than the longest steps on the straight stretches."""
    br = default_branch
    gaps = np.abs(np.diff(br.omega))
    for p in br.points("fold"):
        assert gaps[p.index] < 0.05 * gaps.max()
    assert gaps[-5:-1].min() > 10 * min(gaps[p.index] for p in br.points("fold"))  # (the last step lands on the stop)
