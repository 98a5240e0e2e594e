"""Option objects of shooting, IHB and time integration: the object and the keywords give the
same solution; unknown keywords and bad field values are refused by name with the fix."""

import dataclasses

import numpy as np
import pytest

import periodyn
from periodyn.errors import InputError
from periodyn.examples.dae_examples import duffing, rod_pendulum


@pytest.fixture(scope="module")
def system():
    return duffing(0.05, 0.5, 0.3)


def test_option_objects_are_frozen_and_public():
    for cls in (periodyn.ShootingOptions, periodyn.IHBOptions, periodyn.IntegrationOptions):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(cls(), dataclasses.fields(cls)[0].name, None)


def test_shooting_options_object_equals_keywords(system):
    start = periodyn.ihb(system, 1.1, 7, stability=None)
    opts = periodyn.ShootingOptions(tol=1e-11, samples=31, segments=2,
                                    integration=periodyn.IntegrationOptions(rtol=1e-10, max_step=1.0))
    a = periodyn.shooting(system, 1.1, initial=start, options=opts)
    b = periodyn.shooting(system, 1.1, initial=start, tol=1e-11, samples=31, segments=2, rtol=1e-10, max_step=1.0)
    np.testing.assert_array_equal(a.harmonics, b.harmonics)
    np.testing.assert_array_equal(a.multipliers, b.multipliers)
    # keywords override the object's fields; the orbit is the IHB orbit (independent method)
    c = periodyn.shooting(system, 1.1, initial=start, options=opts, integrator="Radau")
    np.testing.assert_allclose(c.harmonics, a.harmonics, atol=1e-7)
    np.testing.assert_allclose(a.harmonics[15 - 3:15 + 4], start.harmonics[7 - 3:7 + 4], atol=1e-5)


def test_ihb_options_object_equals_keywords():
    s = rod_pendulum()
    a = periodyn.ihb(s, 6.0, 6, options=periodyn.IHBOptions(samples=64, tol=1e-10, stability="monodromy"))
    b = periodyn.ihb(s, 6.0, 6, samples=64, tol=1e-10, stability="monodromy")
    np.testing.assert_array_equal(a.harmonics, b.harmonics)
    np.testing.assert_array_equal(a.multipliers, b.multipliers)


def test_integrate_stiff_options_object_equals_keywords(system):
    args = (system, 1.1, (0.0, 3.0), np.array([0.1]), np.array([0.0]))
    a = periodyn.integrate_stiff(*args, options=periodyn.IntegrationOptions(integrator="BDF", rtol=1e-9, atol=1e-11))
    b = periodyn.integrate_stiff(*args, integrator="BDF", rtol=1e-9, atol=1e-11)
    np.testing.assert_array_equal(a.q, b.q)
    with pytest.raises(InputError, match="'Radau' or 'BDF'"):
        periodyn.integrate_stiff(*args, integrator="DOP853")


@pytest.mark.parametrize("call, name", [
    (lambda s: periodyn.shooting(s, 1.1, tolerance=1e-9), "'tolerance'"),
    (lambda s: periodyn.ihb(s, 1.1, 5, harmonic=3), "'harmonic'"),
    (lambda s: periodyn.integrate_stiff(s, 1.1, (0, 1), [0.0], [0.0], max_steps=3), "'max_steps'"),
])
def test_unknown_keyword_is_refused_by_name(system, call, name):
    with pytest.raises(InputError, match=name):
        call(system)


@pytest.mark.parametrize("make, field, fix", [
    (lambda: periodyn.ShootingOptions(segments=0), "ShootingOptions.segments", "single shooting"),
    (lambda: periodyn.ShootingOptions(tol=-1.0), "ShootingOptions.tol", "such as"),
    (lambda: periodyn.ShootingOptions(segments=2, integration=periodyn.IntegrationOptions(integrator="implicit")),
     "integrator='implicit'", "segments=1"),
    (lambda: periodyn.IHBOptions(stability="fast"), "IHBOptions.stability", "choose one of"),
    (lambda: periodyn.IHBOptions(max_iter=0), "IHBOptions.max_iter", ">= 1"),
    (lambda: periodyn.IntegrationOptions(integrator="euler"), "IntegrationOptions.integrator", "DOP853"),
    (lambda: periodyn.IntegrationOptions(rtol=float("nan")), "IntegrationOptions.rtol", "such as"),
    (lambda: periodyn.IntegrationOptions(steps=33), "IntegrationOptions.steps", "give 34"),
])
def test_bad_field_value_names_the_field_and_the_fix(make, field, fix):
    with pytest.raises(InputError) as err:
        make()
    assert field in str(err.value) and fix in str(err.value)


def test_old_method_keyword_of_shooting_warns_and_keeps_its_meaning(system):
    start = periodyn.ihb(system, 1.1, 7, stability=None)
    with pytest.warns(DeprecationWarning, match="integrator='Radau'"):
        old = periodyn.shooting(system, 1.1, initial=start, method="Radau", tol=1e-10)
    new = periodyn.shooting(system, 1.1, initial=start, integrator="Radau", tol=1e-10)
    np.testing.assert_array_equal(old.harmonics, new.harmonics)
