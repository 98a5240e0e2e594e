"""Branch switching from shooting branches, checked against the IHB switching results
(rod pendulum m = l = 1, eps = 0.1, f = 1, g = 9.81; see test_branch_points).

Shooting continuation of the upper branch finds the symmetry-breaking pitchfork near
2.0826 rad/s; switching there follows the asymmetric branch, whose period doubling near
2.0427 rad/s leads, by a second switch, onto the 2T branch. The same points by IHB with
H = 20 (the harmonic-balance branch of test_branch_points) lie within the truncation error
of the harmonic balance (measured below, 1e-7)."""

import numpy as np
import pytest

from periodyn.arclength import continuation, switch_branch, switch_period_doubling
from periodyn.errors import InputError
from periodyn.examples import rod_pendulum
from periodyn.nonlinear import shooting

H = 20


def _system():
    return rod_pendulum(m1=1, l=1, eps1=0.1, f=1, g=9.81)


def _difference(a, b) -> float:
    """Largest harmonic difference of two solutions, over the harmonics both have."""
    m = min(a.m, b.m)
    return float(np.max(np.abs(a.harmonics[a.m - m:a.m + m + 1] - b.harmonics[b.m - m:b.m + m + 1])))


def _mean_angle(sol) -> float:
    h = sol.harmonics
    return float(h[h.shape[0] // 2, list(sol.coordinate_names).index("phi_rod")].real)


@pytest.fixture(scope="module")
def upper():
    return continuation(_system(), (4.5, 1.95), harmonics=H, method="shooting")


@pytest.fixture(scope="module")
def asymmetric(upper):
    return switch_branch(upper, upper.points("branch-point")[0], 1.95)


@pytest.fixture(scope="module")
def ihb_points():
    up = continuation(_system(), (4.5, 1.95), harmonics=H)
    asym = switch_branch(up, up.points("branch-point")[0], 1.95)
    return up.points("branch-point")[0], asym.points("period-doubling")[0]


def test_shooting_pitchfork_and_asymmetric_branch_agree_with_ihb(upper, asymmetric, ihb_points):
    bp_ihb, pd_ihb = ihb_points
    (bp,) = upper.points("branch-point")
    assert abs(bp.multiplier - 1) < 1e-8 and bp.solution is not None
    # measured |d omega| = 1.2e-7 (pitchfork) and 7.5e-8 (period doubling, below): the H = 20
    # harmonic balance against direct integration
    assert abs(bp.omega - bp_ihb.omega) < 1e-6
    means = np.array([_mean_angle(s) for s in asymmetric.solutions])
    # the switched branch starts on the pitchfork (symmetric: mean -pi/2) and leaves it: its start is
    # corrected where the Jacobian is singular, so the null-direction part is fixed only to about
    # sqrt(tol) (measured 7.3e-7 with scipy 1.17, 2.4e-6 with 1.11), far below the branch's asymmetry
    asymmetry = np.abs(means + np.pi / 2)
    assert np.all(asymmetry[1:] > 1e-3) and asymmetry[0] < 1e-2 * asymmetry[1:].min()
    assert np.max(asymmetric.residual) <= 1e-9
    assert asymmetric.points("branch-point") == [] and asymmetric.points("fold") == []
    (pd,) = asymmetric.points("period-doubling")
    assert abs(pd.multiplier + 1) < 1e-8
    assert abs(pd.omega - pd_ihb.omega) < 1e-6
    assert all(asymmetric.stable[1:pd.index + 1]) and not asymmetric.stable[-1]
    # an asymmetric-branch point is a periodic solution of pointwise shooting from its orbit
    k = len(asymmetric) // 2
    direct = shooting(_system(), asymmetric.omega[k], initial=asymmetric.solutions[k])
    assert _difference(direct, asymmetric.solutions[k]) < 1e-7


def test_switching_at_the_period_doubling_reaches_the_2T_orbit(asymmetric):
    (pd,) = asymmetric.points("period-doubling")
    doubled = switch_period_doubling(asymmetric, pd, 2.039)
    assert doubled.status == "parameter range covered"
    assert all(s.subharmonic == 2 for s in doubled.solutions) and np.max(doubled.residual) <= 1e-9
    sol = doubled.solutions[-1]
    h = sol.harmonics  # harmonics of omega/2: the odd ones are the new, period-2T part
    odd = np.abs(h[np.arange(-sol.m, sol.m + 1) % 2 == 1]).max()
    assert odd > 1e-3
    # the same 2T orbit by pointwise shooting with subharmonic=2 from it, and its T-map is not closed
    direct = shooting(_system(), sol.omega, initial=sol, subharmonic=2)
    assert _difference(direct, sol) < 1e-7
    assert doubled.stable[1]  # stable just past a supercritical period doubling


def test_switching_from_a_shooting_branch_needs_a_refined_point(upper):
    (bp,) = upper.points("branch-point")
    with pytest.raises(InputError, match="not refined"):
        switch_branch(upper, type(bp)("branch-point", bp.index, bp.omega, bp.parameter * 1.001), 2.0)


def test_a_saved_and_loaded_branch_switches_like_the_one_in_memory(upper, tmp_path):
    """The special point's refined unknowns and the problem's references go to the file:
    the loaded branch, given its system, switches at its branch point onto the same
    asymmetric branch (short range: the first points past the pitchfork)."""
    from periodyn.arclength import load_branch
    loaded = load_branch(upper.save(tmp_path / "upper.nc"))
    (bp,) = loaded.points("branch-point")
    for a, b in zip(upper.options["special_unknowns"], loaded.options["special_unknowns"]):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(InputError, match="pass system="):
        switch_branch(loaded, bp, 2.06)
    here = switch_branch(upper, upper.points("branch-point")[0], 2.06)
    there = switch_branch(loaded, bp, 2.06, system=_system())
    assert len(there) == len(here) >= 3
    np.testing.assert_array_equal(there.omega, here.omega)
    for a, b in zip(here.solutions, there.solutions):
        np.testing.assert_array_equal(a.harmonics, b.harmonics)
