"""Sweep files: the valid form, each kind of mistake, and malformed files from hypothesis."""

from __future__ import annotations

import copy
import inspect
import math
import tomllib

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from periodyn.speeds import solve_point
from periodyn.studies.spec import load_sweep_file, parse_sweep, project_root
from periodyn.errors import InputError
from periodyn.examples import pendulum as pendulum_builder

from .toml_edits import junk as junk_values, leaves, replaced, toml_value

VALID = {
    "model": {"example": "pendulum", "parameters": {"zeta": 0.01, "eccentricity": 0.5}},
    "sweep": {"omega": {"start": 0.1, "stop": 1.4, "num": 20, "unit": "omega0"}, "harmonics": 4, "samples": 16,
              "stability": "auto"},
}


def dump(data: dict, prefix: str = "") -> str:
    """Minimal TOML writer: scalars/lists/inline tables, nested dicts as [sections]."""
    scalars = [f"{toml_value(k)} = {toml_value(v)}" for k, v in data.items()
               if not (isinstance(v, dict) and k in ("model", "parameters", "sweep", "grid"))]
    lines = ([f"[{prefix}]"] if prefix else []) + scalars
    for k, v in data.items():
        if isinstance(v, dict) and k in ("model", "parameters", "sweep", "grid"):
            lines.append(dump(v, f"{prefix}.{k}" if prefix else k))
    return "\n".join(lines) + "\n"


def parse(data: dict):
    spec = parse_sweep(dump(data), "test.toml", "test")
    return spec, spec.plan()


def test_valid_file_gives_speeds_in_rad_per_s():
    spec, plan = parse(VALID)
    w0 = math.sqrt(9.81)
    np.testing.assert_allclose(plan.omega, w0 * np.linspace(0.1, 1.4, 20), rtol=1e-12)
    assert plan.reference == ("omega0", pytest.approx(w0))
    assert plan.model.samples == 16 and plan.parameters is None
    assert (spec.harmonics, spec.samples, spec.stability, spec.method) == (4, 16, True, "auto")


def test_units_values_and_grid():
    data = copy.deepcopy(VALID)
    data["sweep"]["omega"] = {"values": [60.0, 120.0], "unit": "rpm"}
    data["sweep"]["grid"] = {"zeta": {"start": 0.01, "stop": 0.03, "num": 3}, "eccentricity": [0.2, 0.5]}
    spec, plan = parse(data)
    np.testing.assert_allclose(plan.omega, [2 * np.pi, 4 * np.pi])
    assert list(plan.parameters) == ["zeta", "eccentricity"]
    np.testing.assert_allclose(plan.parameters["zeta"], [0.01, 0.02, 0.03], rtol=1e-15)
    assert plan.parameters["eccentricity"] == [0.2, 0.5]
    assert plan.model(zeta=0.02, eccentricity=0.2).samples == 16  # fixed parameters and samples kept
    np.testing.assert_allclose(spec.omega_values((1.0, 2.0, 3)), [1.0, 1.5, 2.0])


def test_shipped_sweep_files_are_valid():
    files = sorted((project_root() / "sweeps").glob("*.toml"))
    assert any(f.stem == "pendulum" for f in files)
    assert any(f.stem.startswith("dae_") for f in files)
    for path in files:
        spec = load_sweep_file(path)
        if spec.kind == "continuation":
            from periodyn.dae import DAE

            system = spec.build()  # a DAE built from [model.parameters]
            assert isinstance(system, DAE)
            if path.stem.startswith("dae_"):  # seed 2's examples expose their parameters for continuation
                assert system.parameters
            assert all(system.parameters[k] == v for k, v in spec.parameters.items() if k in system.parameters)
        elif spec.kind in ("transient", "campbell"):
            spec.build()
        elif spec.kind == "chart":
            spec.build(spec.parameter_grid[-1])
        else:
            spec.plan()


def edit(path: tuple, value=None, delete=False) -> dict:
    data = copy.deepcopy(VALID)
    table = data
    for key in path[:-1]:
        table = table[key]
    if delete:
        del table[path[-1]]
    else:
        table[path[-1]] = value
    return data


@pytest.mark.parametrize(
    "data, message",
    [
        (edit(("sweep", "harmonic"), 4), r"\[sweep\]: unknown key 'harmonic'; did you mean 'harmonics'\?"),
        (edit(("model", "parameters", "zeeta"), 0.1), r"unknown key 'zeeta'; did you mean 'zeta'\?"),
        (edit(("model", "example"), "pendelum"), r"unknown example 'pendelum'; did you mean 'pendulum'\? known "),
        (edit(("sweep", "harmonics"), -2), r"harmonics: must be an integer >= 1, got -2"),
        (edit(("sweep", "harmonics"), 2.5), r"harmonics: must be an integer, got a number \(2.5\)"),
        (edit(("sweep", "samples"), 5), r"5 samples cannot resolve 4 harmonics; use samples >= 9"),
        (edit(("sweep", "omega", "start"), -0.1), r"omega.start: must be positive"),
        (edit(("sweep", "omega", "unit"), delete=True), r"omega: missing unit; add unit = \"rad/s\""),
        (edit(("sweep", "omega", "unit"), "omega1"), r"unknown unit 'omega1'; use one of: rad/s, rpm, Hz, omega0"),
        (edit(("sweep", "stability"), "yes"), r"stability: must be true or false"),
        (edit(("sweep", "stability"), "sprase"), r"unknown method 'sprase'; did you mean 'sparse'\?"),
        (edit(("sweep",), delete=True), r"top level: missing required key 'sweep'"),
        (edit(("model", "parameters", "zeta"), "0.01"), r"\[model.parameters\] zeta: must be a number, got a string"),
        (edit(("model", "parameters", "zeta"), -0.5), r"\[model\] pendulum: pendulum zeta must be >= 0"),
        (edit(("model", "parameters", "samples"), 16), r"give samples in \[sweep\]"),
        (edit(("sweep", "grid"), {"zeta": []}), r"\[sweep.grid\] zeta: must be a non-empty list"),
        (edit(("model", "elements"), [{"type": "beam"}]), r"give either example = .* or an element model \(elements\)"),
    ],
)
def test_mistakes_are_named_with_a_fix(data, message):
    with pytest.raises(InputError, match=message) as info:
        parse(data)
    assert str(info.value).startswith("test.toml: ")


def test_bad_toml_and_missing_file(tmp_path):
    with pytest.raises(InputError, match=r"x.toml: not valid TOML: .*line 1"):
        parse_sweep("[model\nexample = 1", "x.toml")
    (tmp_path / "one.toml").write_text("")
    with pytest.raises(InputError, match=r"no sweep file at .*two.toml; files in .*: one.toml"):
        load_sweep_file(tmp_path / "two.toml")


# ----------------------------------------------------------------------------- hypothesis
LEAVES = [("model", "example"), ("model", "parameters", "zeta"), ("model", "parameters", "eccentricity"),
          ("sweep", "omega", "start"), ("sweep", "omega", "stop"), ("sweep", "omega", "num"),
          ("sweep", "omega", "unit"), ("sweep", "harmonics"), ("sweep", "samples"), ("sweep", "stability"),
          ("sweep", "method"), ("sweep", "omega"), ("model", "parameters"), ("sweep",), ("model",)]
REQUIRED = [("model",), ("sweep",), ("model", "example"), ("sweep", "omega"), ("sweep", "harmonics"),
            ("sweep", "omega", "unit"), ("sweep", "omega", "start"), ("sweep", "omega", "num")]
text = st.text(st.characters(exclude_categories=("Cs", "Cc")), max_size=8)  # writable as TOML strings
junk = junk_values(st.integers(-10**6, 10**6), text)
VALID_KEYS = {  # keys each table accepts (the element-model keys switch [model] to the other form)
    (): {"description", "model", "sweep"},
    ("model",): {"example", "parameters", "name", "points", "angles", "elements", "masses", "inertias", "forces",
                 "torques", "gravity", "fixed", "prescribed", "dynamic", "outputs"},
    ("model", "parameters"): set(inspect.signature(pendulum_builder).parameters),
    ("sweep",): {"omega", "harmonics", "samples", "stability", "method", "grid"},
    ("sweep", "omega"): {"start", "stop", "num", "unit", "values"},
}
key_names = st.text(st.characters(min_codepoint=97, max_codepoint=122), min_size=1, max_size=12)


def check_clean(data: dict) -> None:
    """Either a usable plan or an InputError naming the file; nothing else."""
    try:
        parse(data)
    except InputError as exc:
        assert str(exc).startswith("test.toml: ") and len(str(exc)) > len("test.toml: ") + 10


settings_ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@settings_
@given(st.sampled_from(LEAVES), junk)
def test_any_wrong_value_gives_a_clean_error(path, value):
    check_clean(edit(path, value))


@settings_
@given(st.sampled_from(REQUIRED))
def test_missing_required_key_is_an_error(path):
    with pytest.raises(InputError, match="missing"):
        parse(edit(path, delete=True))


@settings_
@given(st.sampled_from([("sweep",), ("model",), ("model", "parameters"), ("sweep", "omega"), ()]), key_names, junk)
def test_unknown_keys_are_refused(table, key, value):
    assume(key not in VALID_KEYS[table])
    data = copy.deepcopy(VALID)
    target = data
    for k in table:
        target = target[k]
    target[key] = value
    with pytest.raises(InputError, match=f"unknown key '{key}'"):
        parse(data)


@settings(max_examples=150, deadline=None)
@given(st.text(max_size=200))
def test_arbitrary_text_gives_a_clean_error(text):
    with pytest.raises(InputError) as info:
        parse_sweep(text, "test.toml").plan()
    assert str(info.value).startswith("test.toml: ")


# ----------------------------------------------------------------------------- element models
ELEMENTS_FILE = project_root() / "sweeps" / "elliptic_pendulum_elements.toml"


def test_element_model_file_builds_the_same_model_as_python():
    from periodyn.examples.elliptic_pendulum import pendulum_from_elements
    from periodyn.examples.pendulum_equation import pendulum
    from periodyn.engine.front import sweep_file

    spec = load_sweep_file(ELEMENTS_FILE)
    model = spec.plan().model
    reference = pendulum_from_elements(samples=64)
    for name in ("mass", "damping", "stiffness", "force"):
        np.testing.assert_array_equal(getattr(model, name), getattr(reference, name))
    ds = sweep_file(spec, omega=(1.0, 4.0, 4), progress=False)
    np.testing.assert_array_equal(ds["omega"].values, [1.0, 2.0, 3.0, 4.0])
    analytic = pendulum(samples=64)  # eq. (29) written by hand
    for k, w in enumerate(ds["omega"].values):
        point = solve_point(analytic.at(w), 12)
        np.testing.assert_allclose(ds["amplitude"].values[k], point.amplitude, rtol=1e-8)
        np.testing.assert_allclose(ds["max_real_exponent"].values[k], point.max_real, rtol=1e-8)


def test_slider_crank_file_matches_the_python_builder():
    from periodyn.examples.slider_crank_rod import slider_crank

    model = load_sweep_file(project_root() / "sweeps" / "slider_crank_elements.toml").plan().model
    reference = slider_crank(damping=0.02, samples=64)
    assert model.output_names == ("midpoint_deflection",) and model.n == 4
    for omega in (150.0, 300.0):  # same equations at the swept speeds, to round-off
        ours, theirs = model.at(omega), reference.at(omega)
        for name in ("mass", "damping", "stiffness", "force", "output_maps"):
            ref = getattr(theirs, name)
            np.testing.assert_allclose(getattr(ours, name), ref, rtol=0, atol=1e-12 * np.abs(ref).max())


def element_text(old: str, new: str) -> str:
    text = ELEMENTS_FILE.read_text()
    assert old in text
    return text.replace(old, new, 1)


@pytest.mark.parametrize(
    "old, new, message",
    [
        ('points = ["P", "B"]', 'points = ["P", "X"]',
         r"\[\[model.elements\]\] #4 \(beam 'pendulum'\): .*unknown nodal coordinate 'X.x'"),
        ('type = "hinge"', 'type = "hing"', r"#2 type: unknown type 'hing'; did you mean 'hinge'\?"),
        ('type = "hinge"\n', "", r"#2: missing required key 'type'"),
        ("B = [0.0, -1.75]", "B = [0.0]", r"\[model.points\] B: must be a pair \[x, y\] of numbers"),
        ("B = 1.0", "B = -1.0", r"\[model.masses\] B: must be >= 0"),
        ('mode = "free"', 'mode = "loose"', r"pin.*mode status 'loose' unknown"),
        ("damping = 0.06", "dampng = 0.06", r"unknown key 'dampng'; did you mean 'damping'\?"),
        ('unit = "rad/s"', 'unit = "omega0"', r"unknown unit 'omega0'; use one of: rad/s, rpm, Hz"),
        ("samples = 64", "samples = 64\n[sweep.grid]\nzeta = [0.1]", r"has no parameters to vary"),
        ("B = 1.0", "B = 0.0", r"el.toml: \[model\] elliptic_pendulum_elements: .*singular mass matrix, the dynamic "
                               r"coordinates \['pendulum'\] move no mass"),
    ],
)
def test_element_model_mistakes(old, new, message):
    with pytest.raises(InputError, match=message):
        parse_sweep(element_text(old, new), "el.toml", "el").plan()


@pytest.mark.parametrize(
    "edits, message",
    [
        ([('fixed = ["O", "B.y"]', 'fixed = ["O"]')], r"sc.toml: \[model\] slider_crank_elements: model "
                                                    r"'slider_crank_elements' is under-constrained"),
        ([("A = [0.15, 0.0]", "A = [0.35, 0.0]"), ("R1 = [0.3, 0.0]", "R1 = [0.4, 0.0]")],
         r"sc.toml: .*Newton iteration on the constraints failed at"),  # rod shorter than crank
    ],
)
def test_mechanism_mistakes(edits, message):
    text = (project_root() / "sweeps" / "slider_crank_elements.toml").read_text()
    for old, new in edits:
        assert old in text
        text = text.replace(old, new, 1)
    with pytest.raises(InputError, match=message):
        parse_sweep(text, "sc.toml", "sc").plan()


ELEMENT_DATA = tomllib.loads(ELEMENTS_FILE.read_text())
ELEMENT_PATHS = [("model",) + p for p in leaves(ELEMENT_DATA["model"])]


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(ELEMENT_PATHS), junk)
def test_any_wrong_value_in_an_element_model_gives_a_clean_error(path, value):
    try:
        parse_sweep(dump(replaced(ELEMENT_DATA, path, value)), "test.toml", "test").plan()
    except InputError as exc:
        assert str(exc).startswith("test.toml: ")
