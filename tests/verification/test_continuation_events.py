"""User continuation events (``periodyn.Event``): a sign change of the user's test between
branch points is located by the special-point refinement and recorded with the user's type;
checked against an independent root search over separate IHB solves."""

import numpy as np
import pytest
from scipy.optimize import brentq

import periodyn
from periodyn.errors import InputError
from periodyn.examples.dae_examples import duffing

A = 0.6  # amplitude of coordinate 0 the event waits for (the branch grows from 0.38 to 0.75)
H = 5
OPTS = dict(harmonics=H, stability=None, confirm=False)


@pytest.fixture(scope="module")
def system():
    return duffing(0.05, 0.5, 0.3)


@pytest.fixture(scope="module")
def branch(system):
    event = periodyn.Event("amplitude A", lambda pt: pt.amplitude[0] - A, tol=1e-10)
    return periodyn.continuation(system, (0.5, 0.9), events=[event], **OPTS)


def test_user_event_is_located_where_an_independent_root_search_puts_it(system, branch):
    (sp,) = branch.points("amplitude A")
    k = sp.index
    assert branch.amplitude[k, 0] < A < branch.amplitude[k + 1, 0]
    assert abs(sp.amplitude[0] - A) <= 1e-10 and abs(sp.test_values[2]) <= 1e-10
    assert branch.omega[k] < sp.omega < branch.omega[k + 1]

    def gap(w):  # separate IHB solves at fixed omega, started from the bracketing branch point
        return periodyn.ihb(system, w, H, initial=branch.solutions[k], tol=1e-12, stability=None).amplitude()[0] - A

    omega = brentq(gap, branch.omega[k], branch.omega[k + 1], xtol=1e-13)
    # the branch's Newton stops at residual 1e-8: omega agrees to that over the slope d amplitude / d omega
    assert abs(sp.omega - omega) <= 1e-7 * omega
    np.testing.assert_allclose(sp.solution.harmonics, periodyn.ihb(system, omega, H, initial=sp.solution, tol=1e-12,
                                                                   stability=None).harmonics, atol=1e-7)


def test_user_event_survives_the_save_load_round_trip(branch, tmp_path):
    loaded = periodyn.load_branch(branch.save(tmp_path / "events.nc"))
    (sp,) = branch.points("amplitude A")
    (back,) = loaded.points("amplitude A")
    assert (back.index, back.omega, back.parameter) == (sp.index, sp.omega, sp.parameter)
    np.testing.assert_array_equal(back.amplitude, sp.amplitude)
    np.testing.assert_array_equal(back.test_values, sp.test_values)


def test_event_point_exposes_the_orbit(system):
    seen = []

    def test(pt):
        seen.append(pt)
        return 1.0

    periodyn.continuation(system, (0.5, 0.55), events=[periodyn.Event("never", test)], harmonics=H, confirm=False)
    pt = seen[-1]
    assert isinstance(pt, periodyn.EventPoint) and pt.omega == pt.parameter
    np.testing.assert_allclose(pt.amplitude, pt.solution.amplitude())
    assert pt.harmonics.shape == (2 * H + 1, 1) and pt.multipliers.shape == (2,)


def test_bad_events_are_refused(system):
    with pytest.raises(InputError, match="callable"):
        periodyn.Event("x", 3.0)
    with pytest.raises(InputError, match="built-in"):
        periodyn.Event("fold", lambda pt: 1.0)
    with pytest.raises(InputError, match="periodyn.Event"):
        periodyn.continuation(system, (0.5, 0.6), events=[lambda pt: 1.0], **OPTS)
    with pytest.raises(InputError, match="distinct"):
        periodyn.ContinuationOptions(events=[periodyn.Event("a", abs), periodyn.Event("a", abs)])
    with pytest.raises(InputError, match="'nan test'.*finite"):
        periodyn.continuation(system, (0.5, 0.6), events=[periodyn.Event("nan test", lambda pt: float("nan"))], **OPTS)
    with pytest.raises(InputError, match="return a float"):
        periodyn.continuation(system, (0.5, 0.6), events=[periodyn.Event("array", lambda pt: [1.0, 2.0])], **OPTS)
