"""The one Newton and the one event classifier / root refinement."""

import numpy as np
import pytest
import scipy.sparse as sp

from periodyn.arclength.events import branch_test, classify, crossing_test, illinois, same_point
from periodyn.errors import ConvergenceError
from periodyn.numerics.newton_iteration import least_squares_factor, newton


def test_newton_quadratic_convergence_dense_and_sparse():
    """x^2 = 2 componentwise: converges to sqrt(2) with residual and iteration count reported."""
    def eq(x):
        return x * x - 2.0, np.diag(2 * x)

    res = newton(eq, np.ones(3), tol=1e-14, max_iter=10)
    np.testing.assert_allclose(res.x, np.sqrt(2), rtol=1e-15)
    assert res.residual <= 1e-14 and 4 <= res.iterations <= 6
    res_sp = newton(lambda x: (eq(x)[0], sp.csc_matrix(eq(x)[1])), np.ones(3), tol=1e-14, max_iter=10)
    np.testing.assert_allclose(res_sp.x, res.x, rtol=0, atol=0)


def test_gauss_newton_projection_and_failure_report():
    """One equation in two unknowns (circle): minimum-norm steps land on it."""
    res = newton(lambda x: (np.array([x @ x - 1.0]), 2 * x[None]), np.array([0.9, 0.3]), tol=1e-14, max_iter=20,
                 factor=least_squares_factor)
    assert abs(res.x @ res.x - 1.0) <= 1e-14
    with pytest.raises(ConvergenceError, match="did not converge.*after 2 iterations; try this") as info:
        newton(lambda x: (np.exp(x) + 1.0, np.diag(np.exp(x))), np.zeros(1), tol=1e-12, max_iter=2, hint="try this")
    assert info.value.iterations == 2 and info.value.residual > 1.0
    with pytest.raises(ConvergenceError, match="singular Jacobian"):
        newton(lambda x: (np.ones(2), np.zeros((2, 2))), np.zeros(2), tol=1e-12, max_iter=3)


def test_classifier_types():
    inside = np.array([0.5, 0.2])
    assert classify(0.3, -0.2, None, None)[0][0] == "fold"
    pd = classify(1.0, 1.0, np.array([-0.9, 0.2]), np.array([-1.1, 0.2]))
    assert [e[0] for e in pd] == ["period-doubling"] and abs(pd[0][2] - 0.5) < 1e-12
    ns = classify(1.0, 1.0, np.array([0.9j, -0.9j]), np.array([1.1j, -1.1j]))
    assert [e[0] for e in ns] == ["neimark-sacker"]
    assert classify(1.0, 1.0, inside, inside) == []
    # a real multiplier through +1: a fold when dp/ds changes sign, else a branch point
    assert [e[0] for e in classify(0.3, -0.2, np.array([0.9, 0.2]), np.array([1.1, 0.2]))] == ["fold"]
    bp = classify(1.0, 1.0, np.array([0.9, 0.2]), np.array([1.1, 0.2]))
    assert [e[0] for e in bp] == ["branch-point"] and abs(bp[0][2] - 0.5) < 1e-12


def test_branch_test_function_changes_sign_only_at_plus_one():
    # det(M - I) sign times the distance of the nearest multiplier from +1
    assert branch_test(np.array([1.2, 0.1])) == pytest.approx(-0.2)
    assert branch_test(np.array([0.8, 0.1])) == pytest.approx(0.2)
    assert branch_test(np.array([0.5 + 0.5j, 0.5 - 0.5j])) == pytest.approx(abs(0.5 + 0.5j - 1))
    assert branch_test(np.array([-1.2, 0.1])) > 0  # a period doubling does not change its sign


def test_illinois_finds_the_root_of_a_bracketed_indicator():
    calls = []

    def g(s, a, b):
        calls.append(s)
        return np.cos(s) - s, s

    s, data = illinois(g, (0.0, 1.0, None), (1.0, np.cos(1.0) - 1.0, None), ftol=1e-14, stol=1e-15)
    assert abs(s - 0.7390851332151607) < 1e-13 and data == s and len(calls) < 15


def test_quadratic_steps_find_the_root_in_fewer_trials():
    """Inverse quadratic steps (fold refinement) on a curved indicator: the same root, to
    the same tolerance, in fewer trials than the Illinois steps alone."""
    def trials(quadratic):
        calls = []

        def g(s, a, b):
            calls.append(s)
            return np.exp(2 * s) - 3.0, s

        s, _ = illinois(g, (0.0, -2.0, None), (1.0, np.exp(2.0) - 3.0, None), ftol=1e-12, stol=1e-15,
                        quadratic=quadratic)
        assert abs(s - np.log(3.0) / 2) < 1e-12
        return len(calls)

    assert trials(True) < trials(False)


def test_hermite_turn_is_exact_for_a_cubic():
    """The fold refinement's first trial: the zero-slope point of the cubic through the end
    values and slopes, exact when p(s) is itself a cubic; None without a sign change."""
    from periodyn.arclength.events import _hermite_turn

    def p(s):
        return 1.0 + 0.5 * s - s ** 2 + 0.2 * s ** 3

    def dp(s):
        return 0.5 - 2.0 * s + 0.6 * s ** 2

    h = 0.9
    assert _hermite_turn(h, p(0.0), p(h), dp(0.0), dp(h)) == pytest.approx((2.0 - np.sqrt(2.8)) / 1.2, abs=1e-14)
    assert _hermite_turn(0.2, p(0.0), p(0.2), dp(0.0), dp(0.2)) is None


def test_two_multipliers_through_one_in_one_bracket_give_one_branch_point():
    """Both refine the one root of the same test function: reported once, not twice."""
    events = classify(1.0, 1.0, np.array([0.9, 0.95, 0.2]), np.array([1.1, 1.05, 0.2]))
    assert [e[0] for e in events] == ["branch-point"]


def test_crossing_test_follows_the_crossing_kind_not_the_largest_multiplier():
    """A real multiplier already outside must not hide a complex pair crossing the circle."""
    a, b = np.array([3.0, 0.9j, -0.9j]), np.array([3.0, 1.1j, -1.1j])
    assert crossing_test(a, "neimark-sacker") < 0 < crossing_test(b, "neimark-sacker")
    assert abs(crossing_test(a, "neimark-sacker") + 0.1) < 1e-15
    assert [e[0] for e in classify(1.0, 1.0, a, b)] == ["neimark-sacker"]


@pytest.mark.parametrize("touch, one", [(4e-10, True), (1e-6, False)])
def test_roots_either_side_of_a_shared_point_are_one_when_it_is_a_root_to_the_tolerance(touch, one):
    """A test function that touches zero at the branch point b shared by two brackets,
    g = touch - k (p - b)^2, has a root in each; refined to |g| < ftol they are one point
    exactly when the touch itself is within ftol (the refinement cannot tell them apart)."""
    ftol, k, a, b, c = 1e-9, 0.4, 6.30, 6.353, 6.41

    def g(p):
        return touch - k * (p - b) ** 2

    def root(lo, hi):
        s, p = illinois(lambda s, *_: (g(lo + s * (hi - lo)), lo + s * (hi - lo)), (0.0, g(lo), lo),
                        (1.0, g(hi), hi), ftol=ftol, stol=1e-14)
        return p

    p1, p2 = root(a, b), root(b, c)
    assert abs(g(p1)) < ftol and abs(g(p2)) < ftol and p1 < b < p2
    assert same_point(p1, g(p1), p2, g(p2), b, g(b), ftol) is one
    assert same_point(p2, g(p2), p1, g(p1), b, g(b), ftol) is one  # symmetric
    # two crossings well apart with a steep test function are never merged
    assert not same_point(6.30, 0.0, 6.41, 0.0, b, 0.05, ftol)


def test_the_driver_merges_one_point_seen_from_adjacent_brackets_and_keeps_the_better_refined():
    """Branch points refined either side of branch point 5 (p = 6.353), where the test
    function is 4e-10: one point (the one with the smaller |test| stays); another type, a
    bracket further on, or a point without refinement is never merged."""
    from periodyn.arclength.branch import SpecialPoint
    from periodyn.arclength.driver import _add_special

    p = [6.2, 6.25, 6.3, 6.32, 6.34, 6.353, 6.37, 6.4]

    def point(typ, k, where, tests):
        return SpecialPoint(typ, k, where, where, test_values=None if tests is None else np.array(tests))

    specials, loose = [], set()
    first = point("branch-point", 4, 6.35297, [-0.2, 4e-10, 3e-10])
    second = point("branch-point", 5, 6.35303, [4e-10, -0.3, -1e-10])
    _add_special(specials, first, p, False, loose)
    _add_special(specials, point("neimark-sacker", 5, 6.35301, [0.01, -0.02, 1e-13]), p, False, loose)
    _add_special(specials, second, p, False, loose)
    assert [(q.type, q.omega) for q in specials] == [("branch-point", 6.35303), ("neimark-sacker", 6.35301)]
    _add_special(specials, point("branch-point", 6, 6.3531, [-0.3, 0.2, 0.0]), p, False, loose)  # g(6.37) = -0.3
    _add_special(specials, point("neimark-sacker", 6, 6.35302, None), p, False, loose)  # refinement failed
    assert len(specials) == 4 and not loose


def test_a_count_change_without_a_sign_change_next_to_a_refined_point_is_that_point():
    """The chain's case (branch points at 6.35301 refined and 6.35298 interpolated): the
    multiplier count changes in two adjacent brackets, the test function only in the first.
    The second is the first seen again, in either order; a failed refinement of a real sign
    change is kept."""
    from periodyn.arclength.branch import SpecialPoint
    from periodyn.arclength.driver import _add_special

    p = [6.344, 6.350035, 6.353038, 6.3560]
    refined = SpecialPoint("branch-point", 1, 6.353013, 6.353013, test_values=np.array([0.13, -2.7e-3, 4e-10]))
    seen_again = SpecialPoint("branch-point", 2, 6.352978, 6.352978)
    specials, loose = [], set()
    _add_special(specials, refined, p, False, loose)
    _add_special(specials, seen_again, p, True, loose)
    assert specials == [refined]
    specials, loose = [], set()
    early = SpecialPoint("branch-point", 0, 6.3490, 6.3490)
    _add_special(specials, early, p, True, loose)
    _add_special(specials, refined, p, False, loose)
    assert specials == [refined] and not loose
    specials, loose = [], set()
    _add_special(specials, refined, p, False, loose)
    _add_special(specials, seen_again, p, False, loose)  # a sign change whose refinement failed: its own point
    assert specials == [refined, seen_again]
