"""Symmetry-breaking branch points: detection, typing, location and switching onto the
asymmetric branch (rod pendulum m = l = 1, eps = 0.1, f = 1, g = 9.81).

The hanging rod driven by a torque f cos(w t) has the symmetry phi -> -pi - phi,
t -> t + T/2: its symmetric orbits have mean angle -pi/2 (only odd harmonics of
phi + pi/2). On the upper branch of the resonance a real multiplier crosses +1 near
w = 2.08 rad/s without a fold; the asymmetric branch born there period-doubles near 2.04.
"""

import numpy as np
import pytest

from periodyn.arclength import confirm_special_points, continuation, load_branch, switch_branch
from periodyn.arclength.confirm import integrated_multipliers
from periodyn.errors import InputError
from periodyn.examples import rod_pendulum
from periodyn.stability.monodromy import monodromy_matrix

H = 20  # harmonics resolving the 2.7 rad swing (with 10 the Galerkin folds and the Floquet +1 disagree)


@pytest.fixture(scope="module")
def upper():
    """The upper (large-swing) branch, reached from high frequency down through the resonance."""
    s = rod_pendulum(m1=1, l=1, eps1=0.1, f=1, g=9.81)
    return continuation(s, (4.5, 1.95), harmonics=H)


@pytest.fixture(scope="module")
def asymmetric(upper):
    return switch_branch(upper, upper.points("branch-point")[0], 1.95)


def _mean_angle(sol) -> float:
    h = sol.harmonics
    return float(h[h.shape[0] // 2, list(sol.coordinate_names).index("phi_rod")].real)


def _monodromy_multipliers(branch, sp) -> np.ndarray:
    """Multipliers of the DOP853 monodromy of the orbit's linearization (not the Magnus path)."""
    prob = branch.problem
    lin = prob.linearization(prob.from_solution(sp.solution), sp.omega, sp.solution.parameters)
    return np.linalg.eigvals(monodromy_matrix(lin.rheo))


def test_pitchfork_is_detected_typed_and_located(upper):
    assert upper.points("fold") == []
    (bp,) = upper.points("branch-point")
    assert 2.07 < bp.omega < 2.09
    k = bp.index
    # no fold: omega keeps decreasing through the bracket while the stability flips
    assert upper.omega[k - 1] > upper.omega[k] > bp.omega > upper.omega[k + 1]
    assert upper.stable[k] != upper.stable[k + 1]
    # test function sign(det(M - I)) min|mu - 1|: opposite signs at the bracket, zero at the point
    ta, tb, t0 = bp.test_values
    assert ta * tb < 0 and abs(t0) < 1e-9
    assert abs(bp.multiplier - 1) < 1e-9
    # the DOP853 monodromy matrix of the located orbit has the multiplier +1 (measured 1.4e-6 off:
    # the 4th-order Magnus path the refinement used)
    assert np.min(np.abs(_monodromy_multipliers(upper, bp) - 1)) < 1e-5
    # the orbit is the symmetric one: mean angle -pi/2
    assert abs(_mean_angle(bp.solution) + np.pi / 2) < 1e-8


def test_critical_eigenvector_is_the_null_vector_of_the_harmonic_balance_jacobian(upper):
    (bp,) = upper.points("branch-point")
    prob = upper.problem
    J = prob.residual_jacobian(prob.from_solution(bp.solution), bp.omega, bp.solution.parameters)[1]
    J = J.toarray() if hasattr(J, "toarray") else np.asarray(J)
    v = bp.eigenvector
    assert abs(np.linalg.norm(v) - 1) < 1e-12
    sv = np.linalg.svd(J, compute_uv=False)
    # measured |J v| = 9e-11 with |J| = 1.7e3; one singular value apart from the rest
    assert np.linalg.norm(J @ v) < 1e-9 * sv[0] and sv[-1] < 1e-3 * sv[-2]
    # it breaks the symmetry: the tangent of the symmetric branch (dp/ds != 0) is not in it
    assert np.linalg.norm(J @ v) < 1e-3 * np.linalg.norm(J @ (prob.from_solution(upper.solutions[bp.index]) -
                                                               prob.from_solution(upper.solutions[bp.index + 1])))


def test_switching_reaches_the_asymmetric_branch_and_its_period_doubling(upper, asymmetric):
    assert all(abs(_mean_angle(s) + np.pi / 2) < 1e-8 for s in upper.solutions)
    means = np.array([_mean_angle(s) for s in asymmetric.solutions])
    assert abs(means[0] + np.pi / 2) < 1e-8 and np.all(np.abs(means[1:] + np.pi / 2) > 1e-3)
    assert asymmetric.points("branch-point") == [] and asymmetric.points("fold") == []
    assert np.max(asymmetric.residual) <= 1e-8
    (pd,) = asymmetric.points("period-doubling")
    assert 2.03 < pd.omega < 2.05 and abs(pd.multiplier + 1) < 1e-9
    assert abs(_mean_angle(pd.solution) + np.pi / 2) > 0.1
    assert np.min(np.abs(_monodromy_multipliers(asymmetric, pd) + 1)) < 1e-5  # measured 1.4e-6
    # stable between the pitchfork and the period doubling (supercritical pitchfork)
    assert all(asymmetric.stable[1:pd.index + 1]) and not asymmetric.stable[-1]


def test_location_agrees_with_the_monodromy_stability_path(upper):
    """Refined on DOP853 monodromy multipliers instead of Magnus: the same point (measured 3e-8)."""
    (bp,) = upper.points("branch-point")
    start = upper.solutions[bp.index - 1]
    ref = continuation(rod_pendulum(m1=1, l=1, eps1=0.1, f=1, g=9.81), (start.omega, 1.95), harmonics=H,
                       initial=start, stability="monodromy")
    (bp_ref,) = ref.points("branch-point")
    assert abs(bp_ref.omega - bp.omega) < 1e-6


def test_switching_needs_a_branch_point(upper):
    (bp,) = upper.points("branch-point")
    with pytest.raises(InputError, match="not a branch point"):
        switch_branch(upper, type(bp)("fold", bp.index, bp.omega, bp.parameter), 2.0)


def test_branch_point_is_confirmed_by_direct_integration(upper, tmp_path):
    """One period of the DAE with its variational equations from the orbits bracketing the
    pitchfork: a real multiplier crosses +1 between them (measured 0 -> 1 outside)."""
    (bp,) = confirm_special_points(upper).points("branch-point")
    assert bp.confirmed is True and bp.check.startswith("confirmed: real > 0 multipliers")
    mu, defect = integrated_multipliers(upper.options["system"], bp.solution)
    # measured |mu - 1| = 7.4e-5: the DAE's own crossing lies that close in omega (H = 20 truncation)
    assert np.min(np.abs(mu - 1)) < 2e-4 and defect < 1e-3
    back = load_branch(confirm_special_points(upper).save(tmp_path / "b.nc")).points("branch-point")[0]
    assert back.confirmed is True and back.check == bp.check
    assert upper.special_points[0].confirmed is None  # unchecked until asked


def test_branch_point_of_too_few_harmonics_is_rejected_by_direct_integration():
    """With H = 10 the harmonic balance puts a +1 crossing near 2.12 rad/s where the DAE has
    none (its pitchfork is at 2.083, outside that bracket): rejected, and the reason says why."""
    s = rod_pendulum(m1=1, l=1, eps1=0.1, f=1, g=9.81)
    br = continuation(s, (4.5, 1.95), harmonics=10, confirm=True)
    (bp,) = br.points("branch-point")
    assert 2.1 < bp.omega < 2.13
    assert bp.confirmed is False and "no crossing" in bp.check and "raise the harmonics" in bp.check
    mu, defect = integrated_multipliers(s, bp.solution)
    assert np.all(np.abs(mu[np.abs(mu.imag) < 1e-9]) < 1) and defect > 0.01
