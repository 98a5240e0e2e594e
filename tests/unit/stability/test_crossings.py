"""The one crossing classifier (periodyn.stability.crossings) behind stability boundaries
and continuation events."""

import numpy as np
import pytest

from periodyn.arclength.events import classify
from periodyn.stability.boundaries import crossing_type
from periodyn.stability.crossings import classify_crossing, is_real, of_kind
from periodyn.stability.floquet import FloquetExponents


@pytest.mark.parametrize("mu, kind", [(1.2, "fold"), (-1.05, "period-doubling"), (1.1 * np.exp(0.7j), "neimark-sacker"),
                                      (1.1 * np.exp(1e-8j), "fold"), (-1.1 * np.exp(1e-8j), "period-doubling")])
def test_the_crossing_multiplier_names_the_loss(mu, kind):
    assert classify_crossing(complex(mu)) == kind


def test_a_complex_pair_needs_both_sides_complex():
    """A pair that turns real on its way out through -1 is a period doubling."""
    assert classify_crossing(-1.1 + 0.0j, -0.9 + 0.1j) == "period-doubling"
    assert classify_crossing(1.1j, 0.9j) == "neimark-sacker"


def test_boundaries_type_by_the_angle_of_the_critical_multiplier():
    """crossing_type's angle tolerance (tol pi) is the classifier's relative imaginary part
    sin(tol pi): the old angle rule on multipliers away from its thresholds."""
    rng = np.random.default_rng(3)
    angles = np.concatenate([rng.uniform(0, np.pi, 200), [0.0, np.pi, 0.5e-3 * np.pi, (1 - 0.5e-3) * np.pi]])
    for a in angles:
        mu = np.array([1.3 * np.exp(1j * a), 0.5])
        fl = FloquetExponents.from_multipliers(mu, 2.0, "test")
        old = "fold" if a < 1e-3 * np.pi else "period-doubling" if a > (1 - 1e-3) * np.pi else "neimark-sacker"
        assert crossing_type(fl) == old


def test_events_classify_through_the_same_classifier():
    assert [e[0] for e in classify(1.0, 1.0, np.array([-0.9, 0.2]), np.array([-1.1, 0.2]))] == ["period-doubling"]
    assert [e[0] for e in classify(1.0, 1.0, np.array([0.9j, -0.9j]), np.array([1.1j, -1.1j]))] == ["neimark-sacker"]
    assert [e[0] for e in classify(1.0, 1.0, np.array([0.9, 0.2]), np.array([1.1, 0.2]))] == ["branch-point"]
    assert [e[0] for e in classify(0.3, -0.2, np.array([0.9, 0.2]), np.array([1.1, 0.2]))] == ["fold"]
    mu = np.array([1.0, -0.5, 0.3 + 0.4j, 0.3 - 0.4j])
    assert list(is_real(mu)) == [True, True, False, False]
    assert of_kind(mu, "real < 0").tolist() == [-0.5] and of_kind(mu, "complex").size == 2
