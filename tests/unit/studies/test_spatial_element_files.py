"""Spatial element models in study files give the Python builders' numbers: the Cardan
shaft sweep (periodyn.examples.cardan), Table I of the rotor (periodyn.examples.rotor_table1,
shaft="spatial"), and a small model using every other element kind (rigid link, spatial
truss, rigid body, independent element with speed-dependent terms, non-uniform prescribed
motion, spatial loads and outputs); every bad value is refused naming the file and key."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import periodyn
from periodyn.errors import InputError
from periodyn.examples.cardan import cardan_shaft
from periodyn.examples.rotor_table1 import TABLE_I_PRESENT, TABLE_I_SPEED_RPM, rotor
from periodyn.model import Model
from periodyn.model.driving import AngleFunction
from periodyn.model.elements import IndependentElement
from periodyn.model.linearization import omega_split
from periodyn.studies.spec import load_sweep_file, parse_sweep, project_root

from .toml_edits import junk as junk_values, leaves, replaced, toml_value

SWEEPS = project_root() / "sweeps"
CARDAN = SWEEPS / "cardan_shaft_elements.toml"
TABLE_I = SWEEPS / "rotor_table1_elements.toml"


def test_cardan_sweep_from_the_file_equals_the_python_builder():
    from periodyn.engine.front import sweep_file

    spec = load_sweep_file(CARDAN)
    model = spec.plan().model
    reference = cardan_shaft(np.pi / 6, 0.01, 64)
    assert model.metadata["omega_b"] == pytest.approx(reference.metadata["omega_b"], rel=1e-12)  # the unit omega_b
    assert model.output_names == reference.output_names and model.n == reference.n == 10
    ds = sweep_file(spec, omega=(0.3, 0.9, 3), progress=False)  # 0.9 omega_b lies in an instability zone
    ours = periodyn.sweep(reference, ds["omega"].values, harmonics=12, samples=64, stability=True, progress=False)
    assert not ds["stable"].values.all() and ds["stable"].values.any()
    for name in ("amplitude", "harmonics", "max_real_exponent"):
        a, b = ds[name].values, ours[name].values
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max(), err_msg=name)
    np.testing.assert_array_equal(ds["stable"].values, ours["stable"].values)


def test_table_i_from_the_file_equals_the_python_builder():
    spec = load_sweep_file(TABLE_I)
    assert spec.kind == "campbell"
    speed = [TABLE_I_SPEED_RPM * np.pi / 30.0]
    ours = periodyn.campbell(spec.build(), speed, modes=8)
    theirs = periodyn.campbell(rotor(shaft="spatial"), speed, modes=8)
    a, b = ours["eigenvalue"].values[0], theirs["eigenvalue"].values[0]
    np.testing.assert_allclose(a, b, rtol=1e-12)
    np.testing.assert_array_equal(ours["whirl"].values, theirs["whirl"].values)
    paper = np.array([value for _, value in TABLE_I_PRESENT])  # and the paper's present column within 0.5 %
    assert np.abs(a - paper).max() / np.abs(paper).min() < 5e-3


# ----------------------------------------------------------------------------- the other kinds
SMALL = """
[model]
name = "whirling_pendulum"
fixed = ["ground", "O"]
dynamic = ["B.x", "B.y"]
gravity = [0.0, 0.0, -9.81]

[model.points]
O = [0.0, 0.0, 0.0]
A = [0.2, 0.0, 0.0]
B = [0.0, 0.0, -0.3]

[model.orientations]
ground = {}
hub = HUB

[model.masses]
B = 0.5

[model.prescribed]
"spin.rotation" = { rate = 1.0, cosines = [0.05], sines = [0.0, 0.02] }

[[model.elements]]
type = "hinge"
name = "spin"
orientations = ["ground", "hub"]
axis = [0.0, 0.0, 2.0]
damping = 0.1

[[model.elements]]
type = "rigid_link"
name = "arm"
points = ["O", "A"]
orientation = "hub"

[[model.elements]]
type = "truss"
name = "string"
points = ["A", "B"]
mass_per_length = 0.1

[[model.rigid_bodies]]
orientation = "hub"
inertia = [[0.02, 0.001, 0.0], [0.001, 0.03, 0.0], [0.0, 0.0, 0.04]]
point = "A"
mass = 0.3

[[model.independent]]
name = "spring"
coordinates = ["B.x", "B.y"]
stiffness = [40.0, 60.0]
stiffness_omega = [[0.0, 0.5], [-0.5, 0.0]]
stiffness_omega2 = [0.01, 0.02]
damping = [[0.3, 0.1], [0.1, 0.4]]
damping_omega = [0.01, 0.0]
mass = [0.05, 0.05]
force = [0.1, -0.2]

[[model.loads]]
point = "B"
direction = [0.0, 1.0, 0.5]
cosines = [0.3]
mean = 0.1

[[model.outputs]]
type = "coordinate"
name = "sway"
coordinate = "B.y"
scale = 0.3

[[model.outputs]]
type = "body_component"
name = "radial"
points = ["O", "B"]
orientation = "hub"
direction = [1.0, 0.0, 0.0]

[sweep]
omega = { values = [3.0, 7.0], unit = "rad/s" }
harmonics = 4
samples = 16
"""


def small_model_in_python(hub=None):
    m = Model("whirling_pendulum", dimension=3)
    m.add_point("O", (0.0, 0.0, 0.0))
    m.add_point("A", (0.2, 0.0, 0.0))
    m.add_point("B", (0.0, 0.0, -0.3))
    m.add_orientation("ground")
    m.add_orientation("hub", hub)
    m.add_hinge("spin", ("ground", "hub"), axis=(0.0, 0.0, 2.0), damping=0.1)
    m.add_rigid_link("arm", ("O", "A"), "hub")
    m.add_truss("string", ("A", "B"), mass_per_length=0.1)
    m.add_mass("B", 0.5)
    m.add_rigid_body("hub", [[0.02, 0.001, 0.0], [0.001, 0.03, 0.0], [0.0, 0.0, 0.04]], point="A", mass=0.3)
    m.add_independent(IndependentElement(
        "spring", ("B.x", "B.y"), stiffness=(np.diag([40.0, 60.0]), np.array([[0.0, 0.5], [-0.5, 0.0]]),
                                            np.diag([0.01, 0.02])),
        damping=(np.array([[0.3, 0.1], [0.1, 0.4]]), np.diag([0.01, 0.0])), mass=0.05 * np.eye(2),
        force=np.array([0.1, -0.2])))
    m.set_gravity((0.0, 0.0, -9.81))
    m.fix("ground")
    m.fix("O")
    m.prescribe("spin.rotation", AngleFunction.fourier([0.05], [0.0, 0.02], rate=1.0))
    m.add_load("B", AngleFunction.fourier([0.3], mean=0.1), direction=(0.0, 1.0, 0.5))
    m.make_dynamic("B.x")
    m.make_dynamic("B.y")
    m.add_coordinate_output("sway", "B.y", scale=0.3)
    m.add_body_component("radial", ("O", "B"), "hub", (1.0, 0.0, 0.0))
    return omega_split(m.compile(), 16)


QUARTER = np.pi / 4   # the hub's reference rotation about z in each form a file takes
C, S, C2, S2 = (float(f(a)) for a in (QUARTER, QUARTER / 2) for f in (np.cos, np.sin))
ROTATION = [[C, -S, 0.0], [S, C, 0.0], [0.0, 0.0, 1.0]]
HUB_FORMS = {"identity": ("{}", None),
             "axis-angle": (f"{{ axis = [0.0, 0.0, 1.0], angle = {QUARTER!r} }}", (C2, 0.0, 0.0, S2)),
             "euler": (f"[{C2!r}, 0.0, 0.0, {S2!r}]", (C2, 0.0, 0.0, S2)),
             "matrix": (repr(ROTATION), ROTATION)}


@pytest.mark.parametrize("form", list(HUB_FORMS))
def test_every_other_kind_from_a_file_equals_the_python_builder(form):
    text, hub = HUB_FORMS[form]
    model = parse_sweep(SMALL.replace("HUB", text), "small.toml", "small").plan().model
    reference = small_model_in_python(hub)
    assert model.n == 2 and model.output_names == ("sway", "radial")
    for omega in (3.0, 7.0):
        ours, theirs = model.at(omega), reference.at(omega)
        for name in ("mass", "damping", "stiffness", "force", "output_maps"):
            ref = getattr(theirs, name)
            np.testing.assert_allclose(getattr(ours, name), ref, rtol=0, atol=1e-12 * np.abs(ref).max(),
                                       err_msg=f"{form} {name}")
    # the speed-dependent independent terms, the motion and the load reached the equations
    assert np.abs(reference.at(7.0).stiffness - reference.at(3.0).stiffness).max() > 1.0
    assert np.ptp(reference.at(3.0).force[:, 1]) > 0.1


def test_a_planar_file_takes_independent_elements_and_more_outputs():
    from periodyn.examples.elliptic_pendulum import pendulum_from_elements

    path = SWEEPS / "elliptic_pendulum_elements.toml"
    extra = """
[[model.independent]]
name = "spring"
coordinates = ["pendulum"]
stiffness = [2.0]
damping_omega = [0.01]

[[model.outputs]]
type = "coordinate"
name = "phi_scaled"
coordinate = "pendulum"
scale = 2.0
"""
    text = path.read_text().replace("\n[sweep]", extra + "\n[sweep]", 1)
    model = parse_sweep(text, "p.toml", "p").plan().model
    plain = pendulum_from_elements(samples=64)
    at, base = model.at(2.0), plain.at(2.0)
    np.testing.assert_allclose(at.mass, base.mass, rtol=1e-14)
    np.testing.assert_allclose(at.stiffness, base.stiffness + 2.0, rtol=1e-14)  # k on the angle itself
    np.testing.assert_allclose(at.damping, base.damping + 0.01 * 2.0, rtol=1e-14)
    np.testing.assert_allclose(at.output_maps[:, -1], base.output_maps[:, 0] / 2.0, rtol=1e-14)


# ----------------------------------------------------------------------------- bad input
def edited(path, old, new):
    text = path.read_text()
    assert old in text, old
    return text.replace(old, new, 1)


@pytest.mark.parametrize("path, old, new, message", [
    (CARDAN, "P1 = [0.43301270189221935, 0.24999999999999997, 0.0]", "P1 = [0.0, 0.0, 0.0]",
     r"#2 \(spatial_beam 'beam1'\): .*zero length"),
    (CARDAN, "axes = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]", "axes = [[0.0, 1.0, 0.0], [0.0, 1.0, 0.0]]",
     r"universal joint 'joint1': the two hinge axes must be perpendicular"),
    (CARDAN, 'orientations = ["shaft_in", "R0"]', 'orientations = ["R0", "R0"]',
     r"universal joint 'joint1' joins orientation node 'R0' to itself"),
    (CARDAN, 'orientations = ["ground_in", "shaft_in"]', 'orientations = ["shaft_in", "shaft_in"]',
     r"hinge 'bearing_in'.*joins orientation node 'shaft_in' to itself"),
    (CARDAN, "axis = [1.0, 0.0, 0.0]", "axis = [0.0, 0.0, 0.0]", r"#1 axis: is zero; give a direction"),
    (CARDAN, "radius = 0.03", "radius = 0.0", r"\[model.sections.shaft\] radius: must be positive"),
    (CARDAN, "poisson_ratio = 0.3", "poisson_ratio = 0.7", r"poisson_ratio: must lie in \(-1, 0.5\)"),
    (CARDAN, 'section = "shaft"', 'section = "shft"', r"#2 section: unknown section 'shft'; declare it"),
    (CARDAN, "inertia = [0.345555, 0.0, 0.0]", "inertia = [-0.345555, 0.0, 0.0]",
     r"rigid_bodies\]\] #1 \('shaft_out'\): .*symmetric positive semi-definite"),
    (CARDAN, "kelvin_voigt = [2.6046106731769697e-05, 3.6872869865564774e-05,",
     "kelvin_voigt = [3.6872869865564774e-05,", r"#2 kelvin_voigt: must be one time constant \(s\) or six"),
    (CARDAN, "frame = { axis", "frame = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]\nframe2 = { axis",
     r"\[model.orientations\] frame: is not a proper rotation matrix"),
    (CARDAN, "[model.points]", "[model.angles]\nphi = 0.0\n\n[model.points]", r"\[model.angles\]: is for planar"),
    (CARDAN, 'type = "spatial_beam"', 'type = "beam"', r"unknown type 'beam'; .*a spatial model has: spatial_beam"),
    (CARDAN, "omega_t = 542.4042140717073", "wt = 542.4042140717073", r"\[model.frequencies\] wt: a reference frequency's name starts with"),
    (CARDAN, 'name = "cardan_shaft_elements"', 'name = "c"\nstations = ["P0"]', r"stations are for a \[campbell\]"),
    (CARDAN, 'mode = "twist.rotation"', 'mode = "twist.turn"', r"outputs\]\] #3 \('twist'\): .*has no mode 'turn'"),
    (CARDAN, "P2 = [0.8660254037844387, 0.49999999999999994, 0.0]", "P2 = [0.866, 0.5]",
     r"\[model.points\] P2: must be a triple \[x, y, z\]"),
    (TABLE_I, 'stations = ["P0", "P1", "P2", "P3", "P4", "P5"]', "",
     r"\[model\] stations: a \[campbell\] study of an element model needs stations"),
    (TABLE_I, "mass = [6.68, 6.68]", "mass = [6.68, -6.68]", r"independent\]\] #4 mass: a mass matrix must be"),
    (TABLE_I, "stiffness = [17512683.46456693, 17512683.46456693]", "stiffness = [1.0, 2.0, 3.0]",
     r"independent\]\] #1 stiffness: must be 2 numbers \(the diagonal\) or 2 rows of 2"),
    (TABLE_I, 'coordinates = ["P0.y", "P0.z"]', 'coordinates = ["P0.y", "P0.w"]',
     r"independent\]\] #1 \('bearing at 0 in'\): .*unknown nodal coordinate 'P0.w'"),
    (TABLE_I, "mass = 4.90355137007874", "mass = 0.0", r"rigid_bodies\]\] #1 mass: must be positive"),
    (TABLE_I, 'section = "carrier"', 'section = { radius = 0.01 }', r"#2 section \(a solid round section\): missing "
                                                                       r"required key 'youngs_modulus'"),
])
def test_bad_values_are_refused_naming_the_file_and_the_key(path, old, new, message):
    text = edited(path, old, new)
    with pytest.raises(InputError, match=r"^bad\.toml: .*" + message):
        spec = parse_sweep(text, "bad.toml", "bad")
        spec.plan() if spec.kind == "sweep" else spec.build()


ROTOR_DATA = tomllib.loads(TABLE_I.read_text())
ROTOR_PATHS = [("model",) + p for p in leaves(ROTOR_DATA["model"])]
junk = junk_values(st.integers(-10, 10), st.text(alphabet="abcP0.yz_ ", max_size=8))


def assert_clean(data: dict, path: tuple, value) -> None:
    """The file with one value replaced builds or is refused by an InputError naming the file."""
    text = "\n".join(f"{k} = {toml_value(v)}" for k, v in replaced(data, path, value).items())
    try:
        parse_sweep(text, "test.toml", "test").build()
    except InputError as exc:
        assert str(exc).startswith("test.toml: ")


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(ROTOR_PATHS), junk)
def test_any_wrong_value_in_a_spatial_model_gives_a_clean_error(path, value):
    assert_clean(ROTOR_DATA, path, value)


CARDAN_DATA = tomllib.loads(CARDAN.read_text())
CARDAN_DATA["sweep"]["samples"] = 8  # the model at a few angles: the checks, not the sweep
CARDAN_PATHS = [("model",) + p for p in leaves(CARDAN_DATA["model"])]


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(CARDAN_PATHS), junk)
def test_any_wrong_value_in_a_jointed_model_gives_a_clean_error(path, value):
    assert_clean(CARDAN_DATA, path, value)
