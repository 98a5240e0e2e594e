"""A prescribed spatial hinge driven over several full turns (its rotation mode is an angle
that the constraints take modulo 2 pi, on the branch nearest the prescribed value).

A massless shaft turns at the prescribed angle theta about x; a disk (inertia J about x) on
a torsional spring (k, c) rides on it and carries a constant load torque T through a
bearing that only measures its rotation. The spring's twist phi obeys the linear
J phi'' + c phi' + k phi = -T exactly (every axis is x), whatever theta: the kinematics and
the trapezoidal one-period map over three turns are checked against that closed form."""

import numpy as np
import pytest

from periodyn.model.kinematics import configuration
from periodyn.model import Model
from periodyn.nonlinear.elements import element_dae
from periodyn.nonlinear.implicit import ImplicitMap

J, K, C, T = 0.5, 200.0, 2.0, 10.0


def _model():
    m = Model("driven_disk", dimension=3)
    for node in ("ground", "shaft", "disk"):
        m.add_orientation(node)
    m.fix("ground")
    m.add_hinge("drive", ("ground", "shaft"), axis=(1, 0, 0))
    m.prescribe("drive.rotation")
    m.add_hinge("spring", ("shaft", "disk"), axis=(1, 0, 0), mode="flexible", stiffness=K, damping=C)
    m.add_hinge("bearing", ("ground", "disk"), axis=(1, 0, 0), torque=T, misalignment="free")
    m.add_rigid_body("disk", np.diag([J, 1.0, 1.0]))
    return m.compile()


def test_kinematics_follow_the_input_over_three_turns():
    """Euler parameters of the shaft and of the disk (twisted by phi) at theta up to 6 pi,
    each configuration continued from the previous one: (cos a/2, sin a/2, 0, 0) up to sign."""
    model = _model()
    i, j = model.coordinate_names.index("shaft.l0"), model.coordinate_names.index("disk.l0")
    x, theta0, phi = model.x_reference, 0.0, 0.3
    for theta in np.linspace(0.0, 6 * np.pi, 31)[1:]:
        x = configuration(model, theta, [phi], start=(x, theta0, [phi]))
        theta0 = theta
        for k, angle in ((i, theta), (j, theta + phi)):
            lam = x[k:k + 4]
            expected = np.array([np.cos(angle / 2), np.sin(angle / 2), 0.0, 0.0])
            assert min(np.abs(lam - expected).max(), np.abs(lam + expected).max()) < 1e-12, theta


@pytest.mark.parametrize("omega", [5.0, 7.3])
def test_implicit_map_over_three_turns_is_the_trapezoidal_map_of_the_closed_form(omega):
    """The map over three input turns (subharmonic 3) from phi* + (0.01, -0.2), phi* = -T / k:
    y(T3) - y* = S (y0 - y*) with S the trapezoidal (Cayley) map of the linear equation."""
    system = element_dae(_model())
    steps = 128
    pmap = ImplicitMap(system, omega, subharmonic=3)
    star = np.array([-T / K, 0.0])
    y0 = star + np.array([0.01, -0.2])
    Y, S = pmap(y0, steps)
    A = np.array([[0.0, 1.0], [-K / J, -C / J]])
    h = 3 * 2 * np.pi / omega / steps
    step = np.linalg.solve(np.eye(2) - 0.5 * h * A, np.eye(2) + 0.5 * h * A)
    expected = np.linalg.matrix_power(step, steps)
    np.testing.assert_allclose(S, expected, atol=1e-9 * np.abs(expected).max())
    np.testing.assert_allclose(Y[-1] - star, expected @ (y0 - star), atol=1e-9)
