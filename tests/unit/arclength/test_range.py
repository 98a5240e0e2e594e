"""The continuation range: bad ranges refused, branches that end exactly on its ends and
never leave it (rod pendulum m = l = 1, eps = 0.1, f = 1, g = 9.81, whose resonance from
8 rad/s down once stepped to omega = -0.122 and crashed in the orbit linearization)."""

import numpy as np
import pytest

from periodyn.arclength import continuation
from periodyn.arclength.palc import ArcPoint, _inside
from periodyn.errors import InputError
from periodyn.examples import rod_pendulum
from periodyn.nonlinear.ihb_solver import ihb


@pytest.fixture(scope="module")
def rod():
    return rod_pendulum(m1=1, l=1, eps1=0.1, f=1, g=9.81)


@pytest.mark.parametrize("omega, words", [((0.5, 0.5), "empty.*two different values"),
                                          ((0.5, np.inf), "finite.*give both ends as numbers"),
                                          ((np.nan, 2.0), "finite"),
                                          ((0.0, 2.0), "positive driving speeds.*0 < start, stop"),
                                          ((3.0, -1.0), "positive driving speeds")])
def test_bad_omega_ranges_are_refused_with_the_fix(rod, omega, words):
    with pytest.raises(InputError, match=r"omega=\(start, stop\) in rad/s.*" + words):
        continuation(rod, omega, harmonics=5)


def test_bad_parameter_range_is_refused(rod):
    with pytest.raises(InputError, match=r"parameter=\('f', start, stop\) is empty"):
        continuation(rod, 3.6, harmonics=5, parameter=("f", 0.2, 0.2))


def test_predictor_is_shortened_onto_the_bounds_and_kept_off_zero():
    pt = ArcPoint(np.zeros(1), 0.5, np.array([0.0, -1.0]), 0.0, 0)
    assert _inside(pt, 0.2, 1, 0.1, 1.0, True) == 0.2  # inside: unchanged
    assert _inside(pt, 2.0, 1, 0.1, 1.0, True) == pytest.approx(0.4)  # lands on lo = 0.1
    assert _inside(pt, 2.0, 1, -np.inf, 1.0, True) == pytest.approx(0.25)  # half the way to 0
    assert _inside(pt, 2.0, 1, -np.inf, 1.0, False) == 2.0


def test_downward_sweep_through_the_resonance_ends_exactly_on_its_stop(rod):
    br = continuation(rod, (8.0, 1.0), harmonics=5)
    assert br.status == "parameter range covered"
    assert br.omega[0] == 8.0 and br.omega[-1] == 1.0 and np.all((br.omega >= 1.0) & (br.omega <= 8.0))
    # the landed end point is the fixed-omega harmonic balance solution there
    end = ihb(rod, 1.0, 5, initial=br.solutions[-1], tol=1e-10, stability=None)
    np.testing.assert_allclose(br.solutions[-1].harmonics, end.harmonics, atol=1e-7)


def test_a_branch_turning_back_ends_on_its_start_side_and_says_so(rod):
    """With H = 20 the small-swing branch from 1 rad/s folds at 3.18 rad/s and returns along
    the middle branch, which leaves the range below 1 rad/s (it stepped to 0.82 before)."""
    br = continuation(rod, (1.0, 8.0), harmonics=20)
    assert br.omega[-1] == 1.0 and np.all((br.omega >= 1.0) & (br.omega <= 8.0))
    assert "turned back and left the range at parameter 1" in br.status and "widen the range" in br.status
    (fold,) = br.points("fold")
    assert 3.17 < fold.omega < 3.19


def test_parameter_continuation_ends_exactly_on_its_stop():
    br = continuation(rod_pendulum(), 3.6, harmonics=8, parameter=("f", 0.02, 0.3), stability=None)
    assert br.parameter[-1] == 0.3 and np.all(br.parameter <= 0.3)
