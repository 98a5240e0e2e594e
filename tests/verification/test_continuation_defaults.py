"""Continuation with its defaults on the rod pendulum (m = l = 1, eps = 0.1, f = 1, g = 9.81):
harmonics grown until the orbit defect is resolved, every special point checked against the
truncation, against shooting references.

References (shooting, DOP853 monodromy; this file's slow test recomputes the second):
``continuation(rod, (8, 1.95), harmonics=20, method="shooting")`` has its pitchfork at
2.0825930216 rad/s, and ``switch_branch`` there the period doubling at 2.0427142181 rad/s
(tests/verification/test_shooting_switching.py); ``continuation(rod, (1, 8),
method="shooting")`` folds at 3.1812228 rad/s and returns along the middle branch (its 400
points reach 1.17 rad/s) with no other special point. With the defaults the IHB chooses H = 32 for (8, 1) (maximum
defect 5.5e-4) and H = 29 for (1, 8) (7.3e-4); with H = 5, as the default was, (1, 8) joins
the middle branch to the resonant one and has folds at 2.637, 2.910, 2.933 and branch points
at 2.724, 2.920 that the shooting reference lacks.
"""

import numpy as np
import pytest

import periodyn.arclength.entry as entry
from periodyn.arclength import continuation, load_branch, switch_branch
from periodyn.arclength.entry import DEFECT_TOL, TruncationWarning, _next_harmonics
from periodyn.arclength.truncation import orbit_defect
from periodyn.examples import rod_pendulum

PITCHFORK, PERIOD_DOUBLING, FOLD = 2.0825930216, 2.0427142181, 3.18122  # shooting, see the module docstring


@pytest.fixture(scope="module")
def rod():
    return rod_pendulum(m1=1, l=1, eps1=0.1, f=1, g=9.81)


@pytest.fixture(scope="module")
def down(rod):
    return continuation(rod, (8.0, 1.0))


def _unflagged(branch) -> list:
    return [(p.type, p.omega) for p in branch.special_points if p.confirmed is not False]


def test_defaults_resolve_the_resonance_and_find_the_pitchfork_and_its_period_doubling(rod, down):
    assert down.status == "parameter range covered" and down.omega[-1] == 1.0
    assert 20 <= down.options["harmonics"] <= 40 and down.options["truncation"].startswith("resolved")
    assert np.max(down.defect) <= DEFECT_TOL
    assert down.defect[-1] == pytest.approx(orbit_defect(rod, down.solutions[-1]))  # the per-point column
    (bp,) = down.special_points
    assert bp.type == "branch-point" and abs(bp.omega - PITCHFORK) < 1e-3  # measured 4e-9
    assert bp.check.startswith("resolved") and bp.defect <= DEFECT_TOL
    asymmetric = switch_branch(down, bp, 1.95)
    (pd,) = asymmetric.special_points
    assert pd.type == "period-doubling" and abs(pd.omega - PERIOD_DOUBLING) < 1e-3  # measured 9e-9
    assert pd.check.startswith("resolved")


def test_defaults_report_only_the_special_points_of_the_shooting_reference(rod):
    up = continuation(rod, (1.0, 8.0))
    assert "turned back" in up.status and np.all((up.omega >= 1.0) & (up.omega <= 8.0))
    assert [t for t, _ in _unflagged(up)] == ["fold"] and abs(_unflagged(up)[0][1] - FOLD) < 1e-4


def test_given_harmonics_are_kept_but_flagged_with_their_spurious_points(rod, tmp_path):
    with pytest.warns(TruncationWarning, match=r"unresolved: orbit defect .* with H = 5 harmonics given.*raise "
                                               "harmonics or leave it out"):
        br = continuation(rod, (1.0, 8.0), harmonics=5)
    assert br.options["harmonics"] == 5 and np.max(br.defect) > DEFECT_TOL
    # 7: the turn-based step control resolves a +1 crossing 0.004 rad/s from the spurious fold at
    # 2.637 (both in one bracket, and so unseen, with the former steps, which found 6)
    assert len(br.special_points) == 7
    # every point the shooting reference lacks is flagged; the fold it has is resolved
    assert [t for t, _ in _unflagged(br)] == ["fold"] and abs(_unflagged(br)[0][1] - FOLD) < 1e-4
    assert all(p.check.startswith("spurious") and "raise the harmonics" in p.check
               for p in br.special_points if p.confirmed is False)
    back = load_branch(br.save(tmp_path / "b.nc"))
    np.testing.assert_array_equal(back.defect, br.defect)
    assert back.options["truncation"] == br.options["truncation"]


def test_chosen_harmonics_resolve_a_short_range_or_warn_at_the_most_allowed(rod, monkeypatch):
    """3.0-3.2 rad/s: the H = 5 orbits leave a defect of 1.2e-2; doubled, they are resolved."""
    br = continuation(rod, (3.0, 3.2))
    assert br.options["harmonics"] == 10 and np.max(br.defect) <= DEFECT_TOL
    assert max(orbit_defect(rod, s) for s in br.solutions) == pytest.approx(np.max(br.defect))
    monkeypatch.setattr(entry, "_H_MAX", 5)
    with pytest.warns(TruncationWarning, match=r"H = 5 harmonics chosen \(the last that traced; at most 5\)"):
        br = continuation(rod, (3.0, 3.2))
    assert br.options["truncation"].startswith("unresolved") and np.max(br.defect) > DEFECT_TOL


def test_harmonics_grow_geometrically_toward_the_tolerance():
    assert _next_harmonics(5, 0.2, None) == 10  # first growth: doubled
    assert _next_harmonics(10, 0.95, (5, 0.2)) == 20  # defect not falling: doubled
    # falling 0.95 -> 0.038 over 10 harmonics reaches 1e-3 after 12 more
    assert _next_harmonics(20, 0.038, (10, 0.95)) == 32
    assert _next_harmonics(20, 0.0011, (10, 0.95)) == 24  # at least H + 4
    assert _next_harmonics(32, 0.5, (20, 0.9)) == 40  # at most the largest chosen


@pytest.mark.slow
def test_shooting_reference_of_the_upward_sweep(rod):
    ref = continuation(rod, (1.0, 8.0), method="shooting")
    assert [p.type for p in ref.special_points] == ["fold"]
    assert abs(ref.special_points[0].omega - FOLD) < 1e-5
    assert ref.omega[-1] < 2.5  # back along the middle branch past the points the H = 5 balance reported
