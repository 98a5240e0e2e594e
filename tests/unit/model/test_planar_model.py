"""Model building, constraint counting and kinematics errors; transfer-function
derivatives against finite differences of the Newton solution."""

import numpy as np
import pytest

from periodyn.errors import ConvergenceError, InputError
from periodyn.examples.slider_crank_rod import slider_crank_model
from periodyn.model.kinematics import configuration, motion, nominal_configurations
from periodyn.model import Model


def four_bar(crank=0.1, coupler=0.35, rocker=0.3, ground=0.4):
    """Crank-rocker four-bar of trusses (crank angle input through a rigid beam)."""
    m = Model(name="four_bar")
    m.add_point("O", (0.0, 0.0))
    m.add_point("A", (crank, 0.0))
    m.add_point("D", (ground, 0.0))
    # B from the triangle A-B-D
    d = ground - crank
    x = (coupler**2 - rocker**2 + d**2) / (2 * d)
    m.add_point("B", (crank + x, np.sqrt(coupler**2 - x**2)))
    m.add_angle("crank")
    m.add_angle("crank_A")
    m.add_beam("crank", ("O", "A"), ("crank", "crank_A"))
    m.add_truss("coupler", ("A", "B"))
    m.add_truss("rocker", ("D", "B"))
    m.fix("O")
    m.fix("D")
    m.prescribe("crank")
    return m


def test_slider_crank_names_and_counts():
    model = slider_crank_model()
    assert model.dynamic_names == ("rod1.bending_p", "rod1.bending_q", "rod2.bending_p", "rod2.bending_q")
    assert model.input_names == ("crank",)
    assert model.n_coordinates == 13


def test_over_and_under_constrained_models_are_refused_with_names():
    m = four_bar()
    m.fix("B.x")
    with pytest.raises(InputError, match="over-constrained"):
        m.compile()
    m = four_bar()
    m.elements.pop()  # drop the rocker: B is free
    with pytest.raises(InputError, match="under-constrained"):
        m.compile()


def test_singular_constraints_name_coordinates_and_equations():
    m = Model(name="dead")
    m.add_point("O", (0.0, 0.0))
    m.add_point("A", (1.0, 0.0))
    m.add_point("B", (2.0, 0.0))
    m.add_truss("t1", ("O", "A"))
    m.add_truss("t2", ("A", "B"))
    m.fix("O")
    m.fix("B")
    with pytest.raises(InputError, match=r"A\.y.*redundant"):
        m.compile()


def test_bad_input_messages():
    m = Model()
    m.add_point("O", (0, 0))
    with pytest.raises(InputError, match="unknown point node 'Q'"):
        m.add_mass("Q", 1.0)
    with pytest.raises(InputError, match="mode status"):
        m.add_beam("b", ("O", "O"), ("a", "b"), modes="elastic")
    with pytest.raises(InputError, match="defined twice"):
        m.add_point("O", (1, 1))


def test_newton_failure_names_the_angle():
    """A crank too long for the four-bar to turn fully: the coupler cannot reach."""
    model = four_bar(crank=0.1, coupler=0.2, rocker=0.12, ground=0.25).compile()
    with pytest.raises(ConvergenceError, match="crank angle theta = "):
        nominal_configurations(model, 16)


def test_four_bar_closes_and_velocities_match_finite_differences():
    model = four_bar().compile()
    X = nominal_configurations(model, 24)
    lengths = np.hypot(*(X[:, [6, 7]] - X[:, [2, 3]]).T)  # coupler A-B
    np.testing.assert_allclose(lengths, 0.35, atol=1e-12)
    h = 1e-6
    for theta in (0.4, 2.0):
        x = configuration(model, theta)
        mo = motion(model, x, np.array([1.0]), np.array([0.0]))
        fd_v = (configuration(model, theta + h) - configuration(model, theta - h)) / (2 * h)
        fd_a = (configuration(model, theta + h) - 2 * x + configuration(model, theta - h)) / h**2
        np.testing.assert_allclose(mo.v, fd_v, atol=1e-8)
        np.testing.assert_allclose(mo.a, fd_a, atol=2e-3)


def test_transfer_derivatives_at_nonzero_deformation_by_finite_differences():
    """Fd, Fdd, Fdv, Fda at q^d != 0 against differences of Newton solutions."""
    model = slider_crank_model()
    qd = np.array([0.01, -0.02, 0.015, 0.005])
    theta, h = 0.7, 1e-5
    x = configuration(model, theta, qd)
    mo = motion(model, x, np.array([1.0, 0, 0, 0, 0]), np.zeros(5))
    F = lambda th, q: configuration(model, th, q)
    for i in range(4):
        e = np.zeros(4)
        e[i] = h
        Fd_i = (F(theta, qd + e) - F(theta, qd - e)) / (2 * h)
        np.testing.assert_allclose(mo.Fd[:, i], Fd_i, atol=1e-8)
        Fdv_i = (F(theta + h, qd + e) - F(theta + h, qd - e) - F(theta - h, qd + e) + F(theta - h, qd - e)) / (4 * h * h)
        np.testing.assert_allclose(mo.Fdv[:, i], Fdv_i, atol=1e-5)
        j = (i + 1) % 4
        f = np.zeros(4)
        f[j] = h
        Fdd_ij = (F(theta, qd + e + f) - F(theta, qd + e - f) - F(theta, qd - e + f) + F(theta, qd - e - f)) / (4 * h * h)
        np.testing.assert_allclose(mo.Fdd[:, i, j], Fdd_ij, atol=1e-5)
    # Fda = d^2 Fd / dtheta^2 at unit speed
    H = 1e-3
    Fd_at = lambda th: motion(model, F(th, qd), np.zeros(5), np.zeros(5)).Fd
    np.testing.assert_allclose(mo.Fda, (Fd_at(theta + H) - 2 * mo.Fd + Fd_at(theta - H)) / H**2, atol=2e-5)


def _flexible_arm():
    """Two flexible beams O-P-Q driven by a prescribed angle at O, with one output of
    every kind."""
    m = Model(name="arm")
    for name, x in (("O", 0.0), ("P", 0.2), ("Q", 0.4)):
        m.add_point(name, (x, 0.0))
    for a in ("a0", "a1", "a2"):
        m.add_angle(a)
    for name, pts, angs in (("b1", ("O", "P"), ("a0", "a1")), ("b2", ("P", "Q"), ("a1", "a2"))):
        m.add_beam(name, pts, angs, modes=("rigid", "flexible", "flexible"), EI=3.0, mass_per_length=0.5)
    m.fix("O")
    m.prescribe("a0")
    m.add_midpoint_deflection("mid", ("O", "Q"), "P", 0.4)
    m.add_coordinate_output("tip_y", "Q.y", scale=0.5)
    m.add_relative_rotation("tip_rotation", ("a0", "a2"))
    m.add_mode_output("b2_end", "b2.bending_q", scale=2.0)
    return m


def test_outputs_chosen_by_the_model_linearize_their_functionals():
    """G q^d equals the change of each output for a small q^d (finite differences of the
    Newton solution); a flexible mode's output row is the unit vector over its scale."""
    from periodyn.kernels.mechanism.outputs import midpoint_deflection
    from periodyn.model.linearization import output_maps

    model = _flexible_arm().compile()
    assert model.output_names == ("mid", "tip_y", "tip_rotation", "b2_end")
    names = {c: i for i, c in enumerate(model.coordinate_names)}
    theta = 0.7
    X = configuration(model, theta)[None]
    G = output_maps(model, X)[0]
    qd = 1e-6 * np.array([1.0, -2.0, 0.5, 3.0])

    def values(x):
        mid = midpoint_deflection(x[model.outputs[0].dofs], 0.4, np.empty(6))
        return np.array([mid, x[names["Q.y"]] / 0.5, x[names["a2"]] - x[names["a0"]]])

    change = values(configuration(model, theta, qd)) - values(X[0])
    np.testing.assert_allclose(change, G[:3] @ qd, rtol=1e-5)
    unit = np.zeros(4)
    unit[model.dynamic_names.index("b2.bending_q")] = 0.5
    np.testing.assert_allclose(G[3], unit, atol=1e-12)


def test_bad_outputs_are_named():
    m = _flexible_arm()
    with pytest.raises(InputError, match="output 'tip_y' is defined twice"):
        m.add_coordinate_output("tip_y", "Q.x")
    with pytest.raises(InputError, match="unknown nodal coordinate 'Q.z'"):
        m.add_coordinate_output("z", "Q.z")
    with pytest.raises(InputError, match="scale must be a finite non-zero number"):
        m.add_coordinate_output("x", "Q.x", scale=0.0)
    with pytest.raises(InputError, match="unknown angle node 'Q'"):
        m.add_relative_rotation("r", ("a0", "Q"))
    with pytest.raises(InputError, match="element 'b2' has no mode 'twist'"):
        m.add_mode_output("m", "b2.twist")


def test_warm_started_configuration_matches_the_continued_one():
    """A configuration continued from a nearby solved one (one Newton solve) equals the
    one continued from the reference; a bad start is refused."""
    model = slider_crank_model()
    qd = np.array([0.01, -0.02, 0.005, 0.03])
    near = configuration(model, 1.0, 0.9 * qd)
    warm = configuration(model, 1.1, qd, start=(near, 1.0, 0.9 * qd))
    cold = configuration(model, 1.1, qd)
    np.testing.assert_allclose(warm, cold, rtol=0.0, atol=1e-12)
    with pytest.raises(InputError, match="start: x must have shape"):
        configuration(model, 1.1, qd, start=(near[:3], 1.0, qd))
