"""The spatial element spine tied to known results: a slider-crank built from spatial
hinges, rigid links and a flexible truss against the planar model and the closed-form
slider position; the Cardan joint's output speed (Schwab & Meijaard 2001, eq. 31); a
torque-free rigid body against Euler's equations integrated independently."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from periodyn.kernels.mechanism import assembly
from periodyn.model.kinematics import configuration, motion, nominal_configurations
from periodyn.model.linearization import linearize
from periodyn.model import Model

R_CRANK, L_ROD, EA, RHOA, M_PIN, M_SLIDER = 0.15, 0.3, 2.0e5, 0.8, 0.3, 0.5


def _planar_slider_crank():
    m = Model("planar")
    m.add_point("O", (0.0, 0.0))
    m.add_point("A", (R_CRANK, 0.0))
    m.add_point("B", (R_CRANK + L_ROD, 0.0))
    m.add_angle("crank")
    m.add_angle("crank_A")
    m.add_beam("arm", ("O", "A"), ("crank", "crank_A"))
    m.add_truss("rod", ("A", "B"), mode="flexible", EA=EA, mass_per_length=RHOA, kelvin_voigt=1e-3)
    m.add_mass("A", M_PIN)
    m.add_mass("B", M_SLIDER)
    m.set_gravity((0.0, -9.81))
    m.fix("O")
    m.fix("B.y")
    m.prescribe("crank", rate=1.0)
    return m.compile()


def _spatial_slider_crank():
    m = Model("spatial", dimension=3)
    m.add_orientation("ground")
    m.add_orientation("crank")
    m.fix("ground")
    m.add_hinge("main", ("ground", "crank"), axis=(0, 0, 1))
    m.prescribe("main.rotation", rate=1.0)
    m.add_point("O", (0.0, 0.0, 0.0))
    m.add_point("A", (R_CRANK, 0.0, 0.0))
    m.add_point("B", (R_CRANK + L_ROD, 0.0, 0.0))
    m.add_rigid_link("arm", ("O", "A"), "crank")
    m.add_truss("rod", ("A", "B"), mode="flexible", EA=EA, mass_per_length=RHOA, kelvin_voigt=1e-3)
    m.add_mass("A", M_PIN)
    m.add_mass("B", M_SLIDER)
    m.set_gravity((0.0, -9.81, 0.0))
    m.fix("O")
    m.fix("B.y")
    m.fix("B.z")
    return m.compile()


def test_spatial_slider_crank_matches_planar_model_and_closed_form():
    planar, spatial = _planar_slider_crank(), _spatial_slider_crank()
    p = 24
    Xp, Xs = nominal_configurations(planar, p), nominal_configurations(spatial, p)
    theta = 2 * np.pi * np.arange(p) / p
    closed = R_CRANK * np.cos(theta) + np.sqrt(L_ROD**2 - (R_CRANK * np.sin(theta)) ** 2)
    for name in ("A.x", "A.y", "B.x"):
        np.testing.assert_allclose(Xs[:, spatial.coordinate_names.index(name)],
                                   Xp[:, planar.coordinate_names.index(name)], atol=1e-12)
    np.testing.assert_allclose(Xs[:, spatial.coordinate_names.index("B.x")], closed, atol=1e-12)
    # the linearized equations of the flexible rod (mass, damping, stiffness, forces) agree
    omega = 40.0
    a, b = linearize(planar, omega, p), linearize(spatial, omega, p)
    for name in ("mass", "damping", "stiffness", "additional_force", "applied_force"):
        got, want = getattr(b, name), getattr(a, name)
        np.testing.assert_allclose(got, want, atol=1e-10 * np.abs(want).max(), err_msg=name)
    assert np.abs(a.stiffness).max() > 1e5 and np.abs(a.additional_force).max() > 1.0


def _cardan(alpha):
    ca, sa = np.cos(alpha), np.sin(alpha)
    turn = np.array([[ca, -sa, 0.0], [sa, ca, 0.0], [0.0, 0.0, 1.0]])  # x onto the output axis
    m = Model("cardan", dimension=3)
    m.add_orientation("ground_in")
    m.add_orientation("ground_out", rotation=turn)
    m.fix("ground_in")
    m.fix("ground_out")
    m.add_orientation("shaft_in")
    m.add_orientation("shaft_out", rotation=turn)
    m.add_hinge("bearing_in", ("ground_in", "shaft_in"), axis=(1, 0, 0))
    m.prescribe("bearing_in.rotation", rate=1.0)
    m.add_hinge("bearing_out", ("ground_out", "shaft_out"), axis=(ca, sa, 0))
    # input arm of the cross in the plane of the shafts at theta = 0, output arm normal to it
    m.add_universal_joint("joint", ("shaft_in", "shaft_out"), axes=[(0, 1, 0), (0, 0, 1)])
    return m.compile()


@pytest.mark.parametrize("alpha", [np.pi / 6, 0.5])
def test_universal_joint_output_speed_is_the_cardan_relation(alpha):
    model = _cardan(alpha)
    p = 48
    X = nominal_configurations(model, p)
    theta = 2 * np.pi * np.arange(p) / p
    arr = model.arrays
    k = model.mode_names.index("bearing_out.rotation")
    e = int(np.nonzero(arr.modes[:, 0] == k)[0][0])
    dofs = arr.dofs[e, :arr.ndof[e]]
    tensors = assembly.allocate_tensors(arr)
    angle, rate = np.empty(p), np.empty(p)
    for j in range(p):
        v = motion(model, X[j], np.ones(1), np.zeros(1)).v
        assembly.element_tensors(arr, X[j], *tensors)
        angle[j] = tensors[0][e, 0]
        rate[j] = tensors[1][e, 0, :dofs.size] @ v[dofs]
    cardan = np.cos(alpha) / (1 - np.sin(alpha) ** 2 * np.cos(theta) ** 2)  # eq. (31)
    np.testing.assert_allclose(rate, cardan, atol=1e-10)
    # the output angle: tan(phi) = tan(theta) / cos(alpha), on the same turn as theta
    unwrapped = theta + np.arctan2(np.sin(theta) * np.cos(theta) * (1 / np.cos(alpha) - 1),
                                   np.cos(theta) ** 2 + np.sin(theta) ** 2 / np.cos(alpha))
    np.testing.assert_allclose(angle, unwrapped, atol=1e-10)
    # continued from the reference on its own, the configuration is the same point of the turn
    for j in range(0, p, 12):
        np.testing.assert_allclose(configuration(model, theta[j]), X[j], atol=1e-11)


def _torque_free_body(J):
    m = Model("top", dimension=3)
    m.add_orientation("body")
    m.add_rigid_body("body", J)
    m.make_dynamic("body")
    return m.compile()


def _euler_reference(J, omega0, t_end):
    """Euler's equations J W' + W x J W = 0 with lam' = 1/2 lam (0, W), integrated on their own."""
    Jinv = np.linalg.inv(J)

    def rhs(t, y):
        lam, W = y[:4], y[4:]
        l0, l1, l2, l3 = lam
        qmat = np.array([[-l1, -l2, -l3], [l0, -l3, l2], [l3, l0, -l1], [-l2, l1, l0]])
        return np.concatenate([0.5 * qmat @ W, Jinv @ -np.cross(W, J @ W)])

    sol = solve_ivp(rhs, (0, t_end), np.concatenate([[1.0, 0, 0, 0], omega0]), rtol=1e-12, atol=1e-13,
                    method="DOP853")
    return sol.y[:4, -1]


def test_torque_free_rigid_body_follows_euler_equations():
    J = np.array([[1.0, 0.1, 0.0], [0.1, 2.0, 0.2], [0.0, 0.2, 3.0]])
    model = _torque_free_body(J)
    omega0 = np.array([0.8, 0.2, -0.5])
    nd, n = model.n_dynamic, model.n_coordinates
    assert model.dynamic_names == ("body.l1", "body.l2", "body.l3")
    x_start = [model.x_reference.copy(), np.zeros(nd)]

    def rhs(t, y):
        qd, qdot = y[:nd], y[nd:]
        x = configuration(model, 0.0, qd, start=(x_start[0], 0.0, x_start[1]))
        x_start[:] = [x, qd]
        Mb, Cb, Kb = (np.empty((nd, nd)) for _ in range(3))
        fd = np.empty(nd)
        assembly.reduced_sample(model.arrays, x, qdot.copy(), np.zeros(nd), np.zeros(n), Mb, Cb, Kb, fd,
                                *(np.empty((n, nd)) for _ in range(3)))
        return np.concatenate([qdot, np.linalg.solve(Mb, -fd)])

    t_end = 1.5
    # lam' = 1/2 lam (0, W) at lam = identity: the dynamic rates are W / 2
    sol = solve_ivp(rhs, (0, t_end), np.concatenate([np.zeros(nd), 0.5 * omega0]), rtol=1e-12, atol=1e-13,
                    method="DOP853")
    lam = configuration(model, 0.0, sol.y[:nd, -1])[model.coordinate_names.index("body.l0"):]
    np.testing.assert_allclose(lam, _euler_reference(J, omega0, t_end), atol=1e-9)


def test_spin_about_a_principal_axis_is_steady():
    """J diagonal, spin about the third axis: lam(t) = (cos(w t / 2), 0, 0, sin(w t / 2)), so the
    reduced residual of that motion vanishes at any time."""
    from periodyn.model.linearization import reduced_residual
    model = _torque_free_body(np.diag([1.0, 2.0, 3.0]))
    w = 2.0
    for t in (0.3, 1.1):
        qd = np.array([0, 0, np.sin(w * t / 2)])
        qd_dot = np.array([0, 0, w / 2 * np.cos(w * t / 2)])
        qd_ddot = np.array([0, 0, -(w / 2) ** 2 * np.sin(w * t / 2)])
        np.testing.assert_allclose(reduced_residual(model, 0.0, qd, qd_dot, qd_ddot, 0.0), 0, atol=1e-12)
