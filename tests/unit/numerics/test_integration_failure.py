"""A time integration that fails before its first output time: a ConvergenceError (a failed
point in a sweep) naming the time reached, not an IndexError from the empty solution."""

from __future__ import annotations

import numpy as np
import pytest

from periodyn.errors import ConvergenceError
from periodyn.numerics.integration import solve


def test_blow_up_before_the_first_output_time_names_the_time_reached():
    # y' = y^2, y(0) = 1 has y = 1 / (1 - t): it blows up at t = 1, before the outputs at 1.5 and 2 s
    with pytest.raises(ConvergenceError, match=r"failed near t=1 s \(of 0 to 2 s\)") as info:
        solve(lambda t, y: y**2, (0.0, 2.0), np.array([1.0]), t_eval=np.array([1.5, 2.0]))
    assert info.value.iterations > 0  # the right-hand side evaluations spent


def test_a_finished_integration_is_unchanged():
    sol = solve(lambda t, y: -y, (0.0, 1.0), np.array([1.0]), t_eval=np.array([0.5, 1.0]))
    np.testing.assert_allclose(sol.y[0], np.exp(-sol.t), rtol=1e-9)
