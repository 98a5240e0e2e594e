"""Property-based tests (hypothesis) over rotor files, element files and DAE builders with
physics as the oracle, and the defects benchmarks/property_run.py found (each failed
before: a traceback or a broken input accepted).

- rotor files: the same eigenvalues as the rotor built in Python (SI or inch/lbf units),
  no growing mode with bearing damping and none damped without it (a conservative
  gyroscopic system);
- element files: the elliptic pendulum of sweeps/elliptic_pendulum_elements.toml with its
  geometry, bob mass and damper changed, against eq. (29) integrated (amplitude) and
  Liouville's sum of the exponents (-2 zeta omega0); a broken element exits 2;
- DAE builders: a non-physical argument is refused naming builder and argument; shooting
  orbits of valid ones have multipliers whose product is exp(tr A T) (Liouville).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import periodyn
from periodyn.cli import main
from periodyn.errors import InputError
from periodyn.examples import duffing, pendulum, rod_pendulum
from periodyn.results import STATUS_SOLVED, load
from periodyn.rotor import Bearing, Rotor, campbell, load_rotor
from periodyn.studies.spec import parse_sweep, project_root
from tests.unit.harmonic.test_balance_truncation import integrated_amplitude

SETTINGS = dict(deadline=None, derandomize=True, phases=[Phase.explicit, Phase.generate],
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
ELEMENTS = (project_root() / "sweeps" / "elliptic_pendulum_elements.toml").read_text()
IMPERIAL = (0.0254, 0.45359237, 4.4482216)
POSITIVE = st.floats(0.1, 10.0)


# ----------------------------------------------------------------------------- rotor files
@st.composite
def rotors(draw) -> dict:
    return {"units": draw(st.sampled_from([(1.0, 1.0, 1.0), IMPERIAL])), "length": draw(st.floats(0.3, 2.0)),
            "elements": draw(st.integers(1, 4)), "diameter": draw(st.floats(0.02, 0.1)),
            "stiffness": draw(st.floats(1e5, 1e8)), "damping": draw(st.sampled_from([0.0, 50.0, 2000.0])),
            "disk": draw(st.one_of(st.none(), st.tuples(st.floats(1.0, 50.0), st.floats(0.01, 1.0))))}


def rotor_file(v: dict) -> str:
    L, m, f = v["units"]
    k, c = v["stiffness"] / (f / L), v["damping"] / (f / L)
    text = (f"[units]\nlength = {L!r}\nmass = {m!r}\nforce = {f!r}\n[material]\nE = {2.1e11 / (f / L ** 2)!r}\n"
            f"density = {7800.0 / (m / L ** 3)!r}\n[[shaft]]\nstart = 0.0\nend = {v['length'] / L!r}\n"
            f"outer_diameter = {v['diameter'] / L!r}\nelements = {v['elements']}\n")
    for at in (0.0, v["length"] / L):
        text += f"[[bearing]]\nat = {at!r}\nkyy = {k!r}\nkzz = {k!r}\ncyy = {c!r}\nczz = {c!r}\n"
    if v["disk"]:
        mass, polar = v["disk"]
        text += (f"[[disk]]\nat = {v['length'] / L!r}\nmass = {mass / (f / L)!r}\npolar = {polar / (f * L)!r}\n"
                 f"diametral = {0.5 * polar / (f * L)!r}\n")
    return text


@settings(max_examples=25, **SETTINGS)
@given(v=rotors())
def test_rotor_files_match_the_python_rotor_and_never_grow(tmp_path, v):
    path = tmp_path / "r.toml"
    path.write_text(rotor_file(v))
    r = Rotor("r")
    r.add_shaft(0.0, v["length"], outer_diameter=v["diameter"], E=2.1e11, density=7800.0, elements=v["elements"])
    for at in (0.0, v["length"]):
        r.add_bearing(Bearing(at, v["stiffness"], v["stiffness"], cyy=v["damping"], czz=v["damping"]))
    if v["disk"]:
        r.add_disk(v["length"], v["disk"][0], v["disk"][1], 0.5 * v["disk"][1])
    speeds = [0.0, 900.0, 2500.0]
    lam = campbell(load_rotor(path), speeds)["eigenvalue"].values
    np.testing.assert_allclose(lam, campbell(r.compile(), speeds)["eigenvalue"].values, rtol=1e-8, atol=1e-8)
    scale = np.abs(lam).max(axis=1, keepdims=True)
    if v["damping"]:
        assert (lam.real <= 1e-9 * scale).all()
    else:
        assert (np.abs(lam.real) <= 1e-7 * scale).all()


# ----------------------------------------------------------------------------- element files
BROKEN_ELEMENTS = [('angles = ["pinion_P", "pendulum"]', 'angles = ["pendulum", "pendulum"]'),
                   ("damping = 0.06264183905346331", "damping = -0.1"), ("B = 1.0", "B = 0.0"),
                   ('type = "hinge"', 'type = "spring"'), ("samples = 64", "samples = 7")]


@settings(max_examples=8, **SETTINGS)
@given(r=st.floats(0.1, 1.0), e=st.floats(0.05, 0.9), length=st.floats(0.3, 3.0), damping=st.floats(0.01, 0.5),
       mass=st.floats(0.2, 5.0), ratio=st.floats(0.2, 1.3), broken=st.sampled_from([None, None, *BROKEN_ELEMENTS]))
def test_element_files_solve_the_elliptic_pendulum_or_are_refused(tmp_path, capsys, r, e, length, damping, mass,
                                                                   ratio, broken):
    text = ELEMENTS
    for old, new in (*([broken] if broken else []), ("C = [0.0, -0.5]", f"C = [0.0, {-r!r}]"), ("P = [0.0, -0.75]", f"P = [0.0, {-(r + e * r)!r}]"),
                     ("B = [0.0, -1.75]", f"B = [0.0, {-(r + e * r + length)!r}]"),
                     ("damping = 0.06264183905346331", f"damping = {damping!r}"), ("B = 1.0", f"B = {mass!r}")):
        text = text.replace(old, new, 1)
    path, out = tmp_path / "e.toml", tmp_path / "e.nc"
    path.write_text(text)
    out.unlink(missing_ok=True)
    w0 = math.sqrt(9.81 / length)
    code = main(["sweep", str(path), "--omega", f"{ratio * w0!r}:{ratio * w0!r}:1", "--out", str(out), "-q",
                 "--workers", "1"])
    err = capsys.readouterr().err
    if broken:
        assert code == 2 and f"{path}" in err and "Traceback" not in err
        return
    assert code == 0, err
    ds = load(out)
    zeta = damping / (2 * w0 * mass * length ** 2)
    if ds["status"].values[0] == STATUS_SOLVED:
        reference = integrated_amplitude(ratio * w0, length, r, e, zeta)
        assert ds["amplitude"].values[0, 0] == pytest.approx(reference, rel=1e-3)
        assert np.sum(ds["exponents"].values[0].real) == pytest.approx(-2 * zeta * w0, rel=1e-6)
    else:
        assert ds["message"].values[0]


# ----------------------------------------------------------------------------- DAE builders
BAD = st.sampled_from([0.0, -1.0, float("nan"), float("inf"), "x", True, None])


@settings(max_examples=20, **SETTINGS)
@given(name=st.sampled_from(["m1", "l", "eps1", "g"]), bad=BAD)
def test_rod_pendulum_refuses_each_non_physical_argument(name, bad):
    if bad == 0.0 and name in ("eps1", "g"):  # no damping, no gravity: physical
        assert rod_pendulum(**{name: bad}).n == 3
        return
    with pytest.raises(InputError, match=rf"rod_pendulum: {name} must be"):
        rod_pendulum(**{name: bad})


@settings(max_examples=6, **SETTINGS)
@given(m1=st.floats(0.5, 2.0), l=st.floats(0.5, 2.0), eps1=st.floats(0.01, 0.2), ratio=st.floats(0.3, 1.5))
def test_rod_pendulum_orbits_obey_liouville(m1, l, eps1, ratio):
    """Reduced to the pin angle, tr A = -eps1 / (m1 l^2 / 3) at every configuration."""
    w = ratio * math.sqrt(1.5 * 9.81 / l)
    orbit = periodyn.shooting(rod_pendulum(m1=m1, l=l, eps1=eps1, f=0.05), w)
    assert abs(np.prod(orbit.multipliers)) == pytest.approx(math.exp(-3 * eps1 / (m1 * l ** 2) * 2 * math.pi / w),
                                                            rel=1e-6)


@settings(max_examples=6, **SETTINGS)
@given(zeta=st.floats(0.02, 0.3), alpha=st.floats(0.0, 1.0), omega0=st.floats(0.5, 3.0), ratio=st.floats(0.3, 2.0))
def test_duffing_ihb_orbits_are_orbits_of_the_ode(zeta, alpha, omega0, ratio):
    """IHB's orbit, shot from, stays (amplitudes agree) and its multipliers multiply to
    exp(-2 zeta omega0 T)."""
    system, w = duffing(zeta=zeta, alpha=alpha, F=0.05, omega0=omega0), ratio * omega0
    ihb = periodyn.ihb(system, w, 10)
    shot = periodyn.shooting(system, w, initial=ihb)
    np.testing.assert_allclose(ihb.amplitude(), shot.amplitude(), rtol=1e-3)
    assert abs(np.prod(shot.multipliers)) == pytest.approx(math.exp(-2 * zeta * omega0 * 2 * math.pi / w), rel=1e-6)


# ----------------------------------------------------------------------------- defects found
@pytest.mark.parametrize("omega", ["x", "12", (1.0, 2.0, 3.0), (1.0,), ("a", 2.0), None, 3.0])
def test_a_continuation_range_that_is_no_pair_of_numbers_is_refused(omega):
    with pytest.raises(InputError, match=r"omega must be \(start, stop\) in rad/s.*; got"):
        periodyn.continuation(duffing(), omega=omega)


@pytest.mark.parametrize("parameter", [("F", 0.1), ("nope", 0.1, 0.2), ("F", "a", 0.2), "F01", ()])
def test_a_parameter_range_that_is_no_name_and_two_numbers_is_refused(parameter):
    with pytest.raises(InputError, match=r"parameter must be \(name, start, stop\) with name in \['F'\]"):
        periodyn.continuation(duffing(), omega=1.0, parameter=parameter)


@pytest.mark.parametrize("stability", [3, None, 1.0, [True]])
def test_stability_that_is_no_bool_or_method_name_is_refused(stability):
    with pytest.raises(InputError, match="stability must be True, False or a stability method's name"):
        periodyn.sweep(pendulum(samples=24), [1.0], 3, stability=stability, progress=False)


def _two_bearing_rotor():
    """A steel shaft of 1 m on two equal bearings, compiled."""
    r = Rotor("r")
    r.add_shaft(0.0, 1.0, outer_diameter=0.05, E=2e11, density=7800.0, elements=2)
    for at in (0.0, 1.0):
        r.add_bearing(Bearing(at, 1e6, 1e6))
    return r.compile()


@pytest.mark.parametrize("speeds", ["fast", ["a", 1.0], {"x": 1}])
def test_campbell_speeds_that_are_no_numbers_are_refused(speeds):
    with pytest.raises(InputError, match="speeds must be a non-empty 1-D array of finite spin speeds"):
        campbell(_two_bearing_rotor(), speeds)


def test_a_sweep_file_with_more_samples_than_a_sweep_needs_is_refused():
    """samples = 200001 went on to sample the Magnus steps at 800004 angles x 100000 harmonics
    (a 596 GiB MemoryError)."""
    text = ('[model]\nexample = "pendulum"\n[sweep]\nomega = { start = 0.5, stop = 1.0, num = 3, unit = "omega0" }\n'
            'harmonics = 2\nstability = "magnus"\nsamples = 200001\n')
    with pytest.raises(InputError, match=r"p\.toml.*\[sweep\] samples.*at most 4001.*use samples = 9"):
        parse_sweep(text, "p.toml").plan()


@pytest.mark.parametrize("modes", [2.5, "2", True])
def test_campbell_modes_that_are_no_integer_are_refused(modes):
    """2.5 and "2" were cut to 2 modes silently."""
    with pytest.raises(InputError, match="modes must be between 1 and"):
        campbell(_two_bearing_rotor(), [0.0], modes=modes)
