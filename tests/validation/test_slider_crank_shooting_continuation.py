"""Shooting continuation of the non-linear slider-crank (an element model with a stiff
flexible rod) on the implicit one-period map, through the resonance near 206 rad/s
(Schwab & Meijaard 2001, Fig. 5): ``continuation(..., method="shooting")`` chooses the
trapezoidal map for element models by itself; each recorded point carries the
Richardson-extrapolated harmonics and error estimate of pointwise implicit shooting."""

import numpy as np
import pytest

import periodyn
from periodyn.errors import InputError
from periodyn.examples.slider_crank_rod import slider_crank, slider_crank_nonlinear

WINDOW = (203.0, 209.0)


@pytest.fixture(scope="module")
def branch():
    system = slider_crank_nonlinear(0.02)
    start = periodyn.periodic_solution(slider_crank(0.02, 64).at(WINDOW[0]), 12)
    first = periodyn.shooting(system, WINDOW[0], initial=start, integrator="implicit")
    return system, periodyn.continuation(system, WINDOW, 12, method="shooting", initial=first, ds_max=0.05)


@pytest.mark.slow  # minutes per run: a stiff element model continued through a resonance
def test_branch_crosses_the_resonance_on_the_implicit_map(branch):
    system, br = branch
    assert br.status == "parameter range covered" and br.omega[-1] >= WINDOW[1] - 1e-9
    assert br.options["shooting_method"] == "auto" and np.max(br.residual) <= 1e-9
    assert all(s.discretization_error is not None for s in br.solutions)
    amp = br.amplitude.max(axis=1)
    j = int(np.argmax(amp))
    assert 0 < j < len(br) - 1  # the resonance peak lies inside the window


def test_implicit_map_refuses_a_parameter_curve_and_a_plain_dae():
    system = slider_crank_nonlinear(0.02)
    name = sorted(system.parameters)[0] if system.parameters else "f"
    with pytest.raises(InputError):
        periodyn.continuation(system, 150.0, 12, method="shooting", parameter=(name, 0.0, 1.0))
    with pytest.raises(InputError, match="element models"):
        periodyn.continuation(periodyn.examples.duffing(), (1.0, 1.1), 5, method="shooting",
                              shooting_method="implicit")
