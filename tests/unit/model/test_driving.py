"""Functions of the driving angle in the builder and in element files: tables read as
trigonometric interpolants, loads placed on coordinates, wrong declarations refused."""

import numpy as np
import pytest

from periodyn.errors import InputError
from periodyn.model import AngleFunction, Model
from periodyn.studies.checks import Checker
from periodyn.studies.elements import check_element_form


def test_samples_reproduce_the_table_and_its_band_limited_interpolant():
    """A table of cos 3 theta + 0.5 sin theta on 8 points (even: Nyquist 4 > 3) is
    reproduced at the grid and between it, with exact derivatives."""
    grid = 2 * np.pi * np.arange(8) / 8
    g = AngleFunction.samples(np.cos(3 * grid) + 0.5 * np.sin(grid))
    np.testing.assert_allclose(g(grid)[0], np.cos(3 * grid) + 0.5 * np.sin(grid), rtol=0, atol=1e-15)
    theta = np.array([0.1, 1.7, 4.0])
    for got, want in zip(g(theta), (np.cos(3 * theta) + 0.5 * np.sin(theta), -3 * np.sin(3 * theta)
                                    + 0.5 * np.cos(theta), -9 * np.cos(3 * theta) - 0.5 * np.sin(theta))):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-14)
    nyquist = AngleFunction.samples([1.0, -1.0, 1.0, -1.0])  # cos(2 theta) exactly
    np.testing.assert_allclose(nyquist(np.array([0.3]))[0], np.cos(0.6), rtol=1e-15)


def _model():
    m = Model()
    m.add_point("O", (0.0, 0.0))
    m.add_point("A", (1.0, 0.0))
    m.add_angle("a")
    return m


def test_loads_on_coordinates_and_points():
    m = _model()
    f = AngleFunction.fourier([2.0])
    m.add_load("A.x", f)
    m.add_load("A", f, direction=(0.0, -3.0))
    m.add_load("a", lambda t: (np.sin(t), np.cos(t), -np.sin(t)))
    assert [(c, w) for c, w, _ in m.angle_loads] == [("A.x", 1.0), ("A.y", -3.0), ("a", 1.0)]


@pytest.mark.parametrize("call, match", [
    (lambda m: m.add_load("A", AngleFunction.fourier([1.0])), "give a direction"),
    (lambda m: m.add_load("A.x", AngleFunction.linear(1.0)), "periodic in theta"),
    (lambda m: m.add_load("A.q", AngleFunction.fourier([1.0])), "unknown nodal coordinate"),
    (lambda m: m.add_load("A.x", 3.0), "expected an AngleFunction"),
    (lambda m: m.prescribe("a", "fast"), "expected an AngleFunction"),
])
def test_wrong_loads_and_inputs_are_refused(call, match):
    with pytest.raises(InputError, match=match):
        call(_model())


def test_prescribed_function_keeps_its_rate():
    m = _model()
    m.prescribe("a", AngleFunction.fourier([-0.1], mean=0.1, rate=2.0))
    assert m.prescribed["a"] == 2.0 and not m.motions["a"].is_linear


@pytest.mark.parametrize("table, match", [
    ({"prescribed": {"a": {"rate": 1.0, "samples": [0.0], "cosines": [1.0]}}}, "not both"),
    ({"prescribed": {"a": {"rate": 1.0, "speed": 2.0}}}, "unknown key 'speed'"),
    ({"loads": [{"coordinate": "A.x"}]}, "samples"),
    ({"loads": [{"point": "A", "samples": [1.0]}]}, "direction"),
    ({"loads": [{"coordinate": "A.x", "point": "A", "samples": [1.0]}]}, "either coordinate"),
    ({"loads": [{"coordinate": "A.x", "rate": 1.0, "samples": [1.0]}]}, "unknown key 'rate'"),
    ({"loads": [{"coordinate": "A.x", "samples": []}]}, "non-empty list"),
])
def test_element_file_function_tables_are_checked(table, match):
    model = {"points": {"O": [0.0, 0.0]}, "elements": [], **table}
    with pytest.raises(InputError, match=match):
        check_element_form(Checker("study.toml"), model)
