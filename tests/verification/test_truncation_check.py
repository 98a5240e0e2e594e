"""Orbit defect and the truncation verdict on the rod pendulum (m = l = 1, eps = 0.1, f = 1,
g = 9.81; the branch point of tests/verification/test_branch_points.py).

With H = 10 the harmonic balance puts a +1 crossing at 2.117 rad/s; the DAE's pitchfork is
at 2.0826 (H = 20 and direct integration). The H = 10 orbit there leaves a DAE residual of
3 % of the force scale between its samples, and the H = 14 branch has no branch point within
1 % of 2.117: spurious. With H = 20 the defect is 4e-5: resolved, left to the integration.
"""

from dataclasses import replace

import numpy as np
import pytest

from periodyn.studies.spec import load_sweep_file, project_root
from periodyn.arclength import confirm_special_points, continuation, load_branch
from periodyn.arclength.truncation import check_truncation, orbit_defect
from periodyn.errors import InputError
from periodyn.examples import rod_pendulum


@pytest.fixture(scope="module")
def system():
    return rod_pendulum(m1=1, l=1, eps1=0.1, f=1, g=9.81)


@pytest.fixture(scope="module")
def branches(system):
    return {H: continuation(system, (4.5, 1.95), harmonics=H) for H in (10, 20)}


def _defect_twin(system, sol, k=997):
    """The same defect from the complex two-sided series (PeriodicSolution evaluation, not the
    IHB's real layout and FFT) at k equally spaced times."""
    t = np.arange(k) * sol.period / k
    l = np.arange(-sol.m, sol.m + 1)
    rates = replace(sol, harmonics=sol.harmonics * (1j * l * sol.base_frequency)[:, None])
    q, qd, qdd, lam = sol(t), sol.velocity(t), rates.velocity(t), sol.lam(t)
    P = dict(system.parameters, **sol.parameters)
    f = system.force(q, qd, t, sol.omega, P)
    Pq = system.constraint_jacobian(q, t, sol.omega, P)
    r1 = np.einsum("kij,kj->ki", system.mass(q), qdd) - f + np.einsum("kc,kcj->kj", lam, Pq)
    return np.max(np.abs(r1)) / np.max(np.abs(f))


def test_defect_matches_an_independent_evaluation_and_falls_with_harmonics(system, branches):
    sols = {H: br.solutions[int(np.argmin(np.abs(br.omega - 2.2)))] for H, br in branches.items()}
    for sol in sols.values():  # maxima on two time grids: measured to differ by 3e-4 and 8e-3
        assert orbit_defect(system, sol) == pytest.approx(_defect_twin(system, sol), rel=0.02)
    # measured 1.9e-2 at H = 10 and 1.0e-5 at H = 20 (omega 2.267)
    assert orbit_defect(system, sols[20]) < 1e-2 * orbit_defect(system, sols[10])


def test_too_few_harmonics_give_a_spurious_branch_point(system, branches):
    (bp,) = check_truncation(branches[10]).points("branch-point")
    assert 2.1 < bp.omega < 2.13 and bp.defect > 1e-2
    assert bp.confirmed is False and bp.check.startswith("spurious: orbit defect")
    assert "H' = 14" in bp.check and "no crossing" in bp.check and "raise the harmonics" in bp.check


def test_enough_harmonics_leave_the_branch_point_to_the_integration(system, branches, tmp_path):
    (bp,) = check_truncation(branches[20]).points("branch-point")
    assert abs(bp.omega - 2.0826) < 1e-3 and bp.defect < 1e-3
    assert bp.confirmed is None and bp.check.startswith("resolved")
    back = load_branch(check_truncation(branches[20]).save(tmp_path / "b.nc")).points("branch-point")[0]
    assert back.defect == bp.defect and back.check == bp.check and back.confirmed is None


def test_an_unresolved_point_that_persists_at_more_harmonics_is_kept(system, branches):
    """defect_tol below the H = 20 defect (3.7e-5) forces the re-solve at H' = 24: the
    crossing is found again within 1 %, resolved there, and the point stays for the
    integration; with defect_tol below the H' = 24 defect too (2.1e-6) it is rejected: neither
    truncation resolves the orbit to that tolerance."""
    (bp,) = check_truncation(branches[20], defect_tol=1e-5).points("branch-point")
    assert bp.confirmed is None and bp.check.startswith("persists") and "H' = 24" in bp.check
    (bp,) = check_truncation(branches[20], defect_tol=1e-9).points("branch-point")
    assert bp.confirmed is False and "unresolved too" in bp.check


def test_bad_options_are_refused(branches):
    with pytest.raises(InputError, match="must exceed"):
        check_truncation(branches[10], harmonics=8)
    with pytest.raises(InputError, match="window"):
        check_truncation(branches[10], window=0.7)
    with pytest.raises(InputError, match="oversample"):
        orbit_defect(branches[10].options["system"], branches[10].solutions[0], oversample=0)


def test_continuation_and_study_files_run_the_truncation_check_alone(system, tmp_path):
    """confirm="truncation": defects and verdicts from the driver, no integration; the study
    file takes the same value and refuses others."""
    br = continuation(system, (4.5, 1.95), harmonics=10, confirm="truncation")
    (bp,) = br.points("branch-point")
    assert bp.confirmed is False and bp.check.startswith("spurious") and "direct integration" not in bp.check
    assert confirm_special_points(br).points("branch-point")[0].check == bp.check  # kept, not integrated
    with pytest.raises(InputError, match="confirm"):
        continuation(system, (4.5, 1.95), harmonics=10, confirm="yes")
    text = (project_root() / "sweeps" / "dae_rod_pendulum.toml").read_text()
    for value, ok in (('"truncation"', True), ("true", True), ('"integration"', False)):
        path = tmp_path / "study.toml"
        path.write_text(text.replace("harmonics = 10", f"harmonics = 10\nconfirm = {value}"))
        if ok:
            assert load_sweep_file(path).options["confirm"] == (value == "true" or "truncation")
        else:
            with pytest.raises(InputError, match="truncation"):
                load_sweep_file(path)


def test_unresolved_point_of_a_parameter_branch_is_flagged():
    """A fold in the forcing amplitude (rod pendulum defaults at 3.3 rad/s) with H = 3: the
    re-solve follows omega only, so the unresolved orbit is flagged by its defect alone."""
    s = rod_pendulum()
    with pytest.warns(UserWarning, match="H = 3 harmonics given"):
        br = continuation(s, 3.3, harmonics=3, parameter=("f", 0.02, 1.0), stability=None, max_points=86,
                          ds_max=0.5)
    (fold,) = br.points("fold")
    assert 0.7 < fold.parameter < 0.75 and fold.defect == pytest.approx(orbit_defect(s, fold.solution))
    assert fold.defect > 1e-3 and fold.confirmed is False
    assert fold.check.startswith("unresolved") and "follows omega, not f" in fold.check
