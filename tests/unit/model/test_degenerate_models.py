"""Malformed models are refused where they are given, naming the argument and the fix,
instead of being solved as another system (a hinge joining a node to itself left the
pendulum undamped; l = -1 built an inverted pendulum; n_rods = 0 raised IndexError)."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import periodyn
from periodyn.errors import InputError
from periodyn.examples import inverted_pendulum, rod_pendulum, slider_chain_pendulum, slider_rod_pendulum
from periodyn.examples.chain import parametric_chain
from periodyn.examples.dae_examples import duffing
from periodyn.examples.pendulum_equation import pendulum_nonlinear
from periodyn.model import Model
from periodyn.studies.spec import parse_sweep

SWEEPS = pathlib.Path(__file__).resolve().parents[3] / "sweeps"


def test_a_hinge_joining_an_angle_to_itself_is_refused_in_an_element_file():
    text = (SWEEPS / "elliptic_pendulum_elements.toml").read_text()
    bad = text.replace('angles = ["pinion_P", "pendulum"]', 'angles = ["pendulum", "pendulum"]')
    assert bad != text
    with pytest.raises(InputError, match=r"pend\.toml.*hinge 'pin'.*joins angle node 'pendulum' to itself"):
        parse_sweep(bad, "pend.toml").plan()


def _two_points(b=(1.0, 0.0)):
    m = Model(name="m")
    m.add_point("A", (0.0, 0.0))
    m.add_point("B", b)
    m.add_angle("a")
    m.add_angle("b")
    return m


def test_degenerate_elements_are_refused_by_the_builder():
    with pytest.raises(InputError, match="joins point node 'A' to itself"):
        _two_points().add_truss("t", ("A", "A"))
    with pytest.raises(InputError, match="joins angle node 'a' to itself"):
        _two_points().add_beam("b", ("A", "B"), ("a", "a"))
    with pytest.raises(InputError, match="zero length"):
        _two_points((0.0, 0.0)).add_beam("b", ("A", "B"), ("a", "b"))
    with pytest.raises(InputError, match="EI must be finite and >= 0"):
        _two_points().add_beam("b", ("A", "B"), ("a", "b"), EI=-1.0)
    with pytest.raises(InputError, match="damping must be finite"):
        _two_points().add_hinge("h", ("a", "b"), damping=np.nan)
    _two_points().add_hinge("h", ("a", "b"), stiffness=2.0, damping=0.1)  # a proper hinge is accepted


@pytest.mark.parametrize("builder, kwargs, name", [
    (rod_pendulum, {"l": -1.0}, "l"), (rod_pendulum, {"m1": 0.0}, "m1"), (rod_pendulum, {"eps1": -0.1}, "eps1"),
    (rod_pendulum, {"g": np.nan}, "g"), (rod_pendulum, {"f": np.inf}, "f"),
    (inverted_pendulum, {"l": -1.0}, "l"), (inverted_pendulum, {"kappa": 0.0}, "kappa"),
    (slider_rod_pendulum, {"m2": -0.5}, "m2"), (slider_rod_pendulum, {"k1": "stiff"}, "k1"),
    (slider_chain_pendulum, {"l": 0.0}, "l"), (slider_chain_pendulum, {"m": -0.025}, "m"),
    (duffing, {"omega0": 0.0}, "omega0"), (duffing, {"zeta": -0.05}, "zeta"),
    (pendulum_nonlinear, {"length": -1.0}, "length"), (parametric_chain, {"mass": 0.0}, "mass"),
])
def test_dae_builders_refuse_non_physical_arguments(builder, kwargs, name):
    with pytest.raises(InputError, match=rf"{builder.__name__}: {name} must be"):
        builder(**kwargs)


@pytest.mark.parametrize("n_rods", [0, -3, 2.5, True])
def test_slider_chain_needs_at_least_one_rod(n_rods):
    with pytest.raises(InputError, match="n_rods must be an integer >= 1"):
        slider_chain_pendulum(n_rods=n_rods)


def test_valid_builder_arguments_still_build():
    assert rod_pendulum(l=2.0).n == 3 and slider_chain_pendulum(n_rods=1).n == 5


def test_dae_refuses_nan_complex_and_empty_masses():
    force = lambda q, qd, t, w: -q  # noqa: E731
    with pytest.raises(InputError, match="mass has NaN or inf"):
        periodyn.DAE(np.array([[np.nan]]), force)
    with pytest.raises(InputError, match="mass must be a real numeric array"):
        periodyn.DAE(np.array([[1.0 + 1j]]), force)
    with pytest.raises(InputError, match=r"mass must be a square \(n,n\) array \(n >= 1\)"):
        periodyn.DAE(np.zeros((0, 0)), force)
    with pytest.raises(InputError, match=r"mass\(q0\) has NaN or inf"):
        periodyn.DAE(lambda q: np.array([[np.nan]]), force, n=1)
    with pytest.raises(InputError, match="q0 has NaN or inf"):
        periodyn.DAE(np.eye(1), force, q0=[np.nan])
    assert periodyn.DAE(np.eye(1), force).n == 1
