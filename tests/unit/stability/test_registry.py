"""The one registry of stability methods (periodyn.stability.methods): a method registered
there serves scalar calls, sweeps (batched and point by point), boundaries and orbits
alike; ``stability=`` names it."""

import dataclasses

import numpy as np
import pytest

import periodyn
from periodyn.errors import InputError
from periodyn.speeds import SpeedSolver, solve_point
from periodyn.stability import methods
from periodyn.stability.boundaries import stability_boundaries
from periodyn.stability.magnus import magnus_steps
from periodyn.stability.monodromy import monodromy_exponents


def fine_magnus(system, operator, steps=None):
    """Demonstration method: fixed-step Magnus with twice the default steps."""
    fl = monodromy_exponents(system, "magnus", steps or 2 * magnus_steps(system.samples))
    return dataclasses.replace(fl, method="fine-magnus")


@pytest.fixture
def registry(monkeypatch):
    """The registry with the demonstration method added (restored afterwards)."""
    monkeypatch.setattr(methods, "REGISTRY", dict(methods.REGISTRY))
    methods.register(methods.StabilityMethod("fine-magnus", "Magnus with twice the default steps", fine_magnus,
                                             system=True))
    return methods.REGISTRY


def test_the_vocabulary_is_the_registry():
    assert set(methods.names()) >= {"auto", "hill", "sparse", "dense", "monodromy", "magnus"}
    assert all(m.description and m.name == name for name, m in methods.REGISTRY.items())
    with pytest.raises(InputError, match="unknown method 'fast'.*choose one of"):
        methods.check_method("fast")
    with pytest.raises(InputError, match="registered already"):
        methods.register(methods.REGISTRY["dense"])
    assert methods.method_named("auto").rule == (
        "auto: on element models where it is estimated cheaper the method reduced, then "
        "Magnus monodromy with step doubling where its error estimate (Richardson, N vs N/2 steps) is "
        "below the stability tolerance and the verdict cannot flip, at less than the estimated cost of Hill; "
        "else dense or sparse Hill, whichever is estimated cheaper (per point: variable stability_method)")


def test_a_registered_method_serves_scalar_calls_sweeps_and_boundaries(registry):
    model = periodyn.examples.pendulum(samples=32)
    w0 = model.metadata["omega0"]
    speeds = np.array([0.5, 0.95, 1.2]) * w0
    scalar = [periodyn.characteristic_exponents(model.at(w), 4, method="fine-magnus") for w in speeds]
    assert {fl.method for fl in scalar} == {"fine-magnus"}
    reference = monodromy_exponents(model.at(speeds[1]), "magnus", 2 * magnus_steps(32))
    np.testing.assert_array_equal(scalar[1].exponents, reference.exponents)
    ds = periodyn.sweep(model, speeds, 4, stability="fine-magnus", progress=False)
    assert set(ds.stability_method.values) == {"fine-magnus"}
    np.testing.assert_array_equal(ds.max_real_exponent.values, [fl.max_real for fl in scalar])
    callable_model = periodyn.sweep(model.at, speeds[:1], 4, stability="fine-magnus", progress=False)
    assert callable_model.stability_method.values[0] == "fine-magnus"
    found = stability_boundaries(model.at, np.array([0.85, 0.95]) * w0, 4, stability="fine-magnus", xtol=1e-8)
    magnus = stability_boundaries(model.at, np.array([0.85, 0.95]) * w0, 4, stability="magnus", xtol=1e-8)
    assert len(found) == len(magnus) == 1 and found[0].kind == magnus[0].kind
    assert abs(found[0].omega - magnus[0].omega) < 1e-4 * w0
    orbit = periodyn.ihb(periodyn.examples.pendulum_nonlinear(), 0.8 * w0, 5, stability="fine-magnus")
    assert orbit.stability.method == "fine-magnus"


def test_stability_names_the_method_and_method_is_deprecated():
    model = periodyn.examples.pendulum(samples=32)
    speeds = np.array([0.6, 1.1]) * model.metadata["omega0"]
    new = periodyn.sweep(model, speeds, 12, stability="dense", progress=False)
    with pytest.warns(DeprecationWarning, match=r"stability='dense'"):
        old = periodyn.sweep(model, speeds, 12, method="dense", progress=False)
    np.testing.assert_array_equal(new.exponents.values, old.exponents.values)
    assert new.attrs["method"] == old.attrs["method"] == "dense"
    assert set(new.stability_method.values) == {"dense"}
    off = periodyn.sweep(model, speeds, 12, stability=False, progress=False)
    assert off.attrs["stability_methods"] == "none (stability off)"
    with pytest.raises(InputError, match="disagree"), pytest.warns(DeprecationWarning):
        periodyn.sweep(model, speeds, 12, stability="dense", method="sparse", progress=False)
    with pytest.raises(InputError, match="unknown method 'fast'"):
        periodyn.sweep(model, speeds, 12, stability="fast", progress=False)
    system = model.at(speeds[0])
    with pytest.warns(DeprecationWarning):
        point = solve_point(system, 12, method="magnus")
    assert point.method == solve_point(system, 12, "magnus").method == "magnus"
    with pytest.warns(DeprecationWarning):
        assert SpeedSolver(model, 12, method="sparse").method == "sparse"


def test_hill_is_the_cheaper_hill_method_everywhere():
    """"hill" (the orbits' name) is what "auto" on an operator alone takes."""
    model = periodyn.examples.pendulum(samples=32)
    w = 1.1 * model.metadata["omega0"]
    hill = periodyn.characteristic_exponents(model.at(w), 12, method="hill")
    chosen, reason = methods.choose_method(periodyn.harmonic.HarmonicOperator.for_system(model.at(w), 12).at(w))
    assert hill.method == chosen and hill.reason == reason
    batch = SpeedSolver(model, 12, "hill").solve_many([w])  # dense: stacked LAPACK, equal to round-off
    np.testing.assert_allclose(batch.exponents[0], hill.exponents, rtol=1e-13)
    assert batch.method[0] == chosen


def test_boundaries_old_method_keyword_warns_and_keeps_its_meaning():
    model = periodyn.examples.pendulum(samples=32)
    w0 = model.metadata["omega0"]
    grid = np.array([0.85, 0.95]) * w0
    with pytest.warns(DeprecationWarning, match=r"stability_boundaries\(method=\.\.\.\) is deprecated"):
        old = stability_boundaries(model.at, grid, 4, method="magnus", xtol=1e-8)
    new = stability_boundaries(model.at, grid, 4, stability="magnus", xtol=1e-8)
    assert [(b.omega, b.kind) for b in old] == [(b.omega, b.kind) for b in new]
    with pytest.raises(InputError, match="disagree"), pytest.warns(DeprecationWarning):
        stability_boundaries(model.at, grid, 4, stability="dense", method="magnus")
