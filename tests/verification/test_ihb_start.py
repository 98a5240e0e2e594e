"""The default IHB start: from the static configuration, and when that fails from a slower
speed stepped up to the requested one; an explicit message when nothing works."""

import numpy as np
import pytest

from periodyn.arclength import continuation
from periodyn.nonlinear import ihb
from periodyn.nonlinear.ihb_solver import IHBProblem
from periodyn.errors import ConvergenceError
from periodyn.examples import inverted_pendulum

H = 10


def test_inverted_rod_at_60_rad_s_starts_by_default_on_the_orbit_continuation_reaches():
    s = inverted_pendulum()
    prob = IHBProblem(s, H)
    with pytest.raises(ConvergenceError):  # Newton from the static tilt alone does not converge here
        prob.newton(prob.initial(omega=60.0), 60.0, None, 1e-8, 30)
    sol = ihb(s, 60.0, H)
    assert sol.residual < 1e-8
    # the same orbit as arc-length continuation from 14 rad/s, then Newton at 60 from its nearest point
    br = continuation(s, (14.0, 60.5), harmonics=H, stability=None)
    assert br.status == "parameter range covered"
    k = int(np.argmin(np.abs(br.omega - 60.0)))
    ref = ihb(s, 60.0, H, initial=br.solutions[k], stability=None)
    np.testing.assert_allclose(sol.harmonics, ref.harmonics, atol=1e-9)
    assert sol.stable  # the tilted orbit at 60 rad/s, stable (Magnus multipliers)


def test_a_start_that_fails_says_what_was_tried_and_what_to_change():
    s = inverted_pendulum()
    with pytest.raises(ConvergenceError) as err:
        ihb(s, 60.0, H, max_iter=1)
    msg = str(err.value)
    assert "static configuration at 60 rad/s" in msg and "halving the speed" in msg and "initial=" in msg
