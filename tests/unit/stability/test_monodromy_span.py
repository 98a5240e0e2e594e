"""The DOP853 monodromy at a driving period spanning millions of natural periods never
returned (elliptic pendulum at 1e-7 rad/s); it is refused naming the alternatives, and a
sweep records such a speed as a failed point."""

from __future__ import annotations

import numpy as np
import pytest

from periodyn import characteristic_exponents
from periodyn.errors import ConvergenceError
from periodyn.examples import pendulum
from periodyn.results import STATUS_FAILED, STATUS_SOLVED
from periodyn.stability.monodromy import MAX_NATURAL_PERIODS


def test_a_period_of_millions_of_natural_periods_is_refused():
    model = pendulum(samples=32)
    with pytest.raises(ConvergenceError, match=r"3\.13e\+07 natural periods .*Hill's method"):
        characteristic_exponents(model.at(1e-7), 1, method="monodromy")
    # the count is omega0 / omega for the pendulum: just beyond the limit is refused as well
    with pytest.raises(ConvergenceError, match="natural periods"):
        characteristic_exponents(model.at(0.99 * model.metadata["omega0"] / MAX_NATURAL_PERIODS), 1, "monodromy")


def test_a_sweep_fails_only_the_refused_speed():
    from periodyn.engine.front import sweep

    model = pendulum(samples=32)
    ds = sweep(model, np.array([1e-7, model.metadata["omega0"]]), 4, stability="monodromy", progress=False)
    assert list(ds["status"].values) == [STATUS_FAILED, STATUS_SOLVED]
    assert "natural periods" in str(ds["message"].values[0])
