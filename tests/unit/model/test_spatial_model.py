"""The spatial model builder: coordinates, orientation nodes, and bad input (a joint axis
of zero length, an unknown node, a singular mass, a planar call on a spatial model)."""

import numpy as np
import pytest

from periodyn import InputError
from periodyn.model import Model
from periodyn.model.spatial import euler_parameters, rotation_of


def _spatial():
    m = Model("s", dimension=3)
    m.add_orientation("ground")
    m.fix("ground")
    m.add_orientation("shaft")
    return m


def test_coordinates_and_reference_rotation():
    m = Model("s", dimension=3)
    m.add_point("P", (1.0, 2.0, 3.0))
    R = rotation_of(np.array([0.2, -0.5, 0.7, 0.1]) / np.linalg.norm([0.2, -0.5, 0.7, 0.1]))
    m.add_orientation("B", rotation=R)
    m.fix("P")
    m.fix("B")
    c = m.compile()
    assert c.coordinate_names == ("P.x", "P.y", "P.z", "B.l0", "B.l1", "B.l2", "B.l3")
    assert c.mode_names == ("B.normalization",) and c.dimension == 3
    np.testing.assert_allclose(rotation_of(c.x_reference[3:]), R, atol=1e-14)
    np.testing.assert_allclose(euler_parameters(rotation_of([0.0, 0.6, 0.0, 0.8])), [0.0, 0.6, 0.0, 0.8], atol=1e-15)
    # fixing an orientation fixes all Euler parameters but its largest; the normalization does the rest
    assert sum("fixed coordinate 'B." in label for label in c.constraint_labels) == 3


def test_zero_length_axis_names_the_fix():
    m = _spatial()
    with pytest.raises(InputError, match="axis must be a finite non-zero 3-vector"):
        m.add_hinge("h", ("ground", "shaft"), axis=(0, 0, 0))
    with pytest.raises(InputError, match="axis must be a finite non-zero 3-vector"):
        m.add_hinge("h", ("ground", "shaft"))
    m.add_orientation("other")
    with pytest.raises(InputError, match="perpendicular"):
        m.add_universal_joint("u", ("shaft", "other"), axes=[(1, 0, 0), (1, 1, 0)])


def test_unknown_nodes_name_the_fix():
    m = _spatial()
    with pytest.raises(InputError, match="unknown orientation node 'nowhere'; add it with add_orientation"):
        m.add_hinge("h", ("ground", "nowhere"), axis=(1, 0, 0))
    with pytest.raises(InputError, match="unknown orientation node"):
        m.add_rigid_body("nowhere", np.eye(3))
    with pytest.raises(InputError, match="unknown point node"):
        m.add_rigid_link("l", ("A", "B"), "shaft")
    with pytest.raises(InputError, match="unknown orientation node"):
        m.add_universal_joint("u", ("shaft", "nowhere"), axes=[(0, 1, 0), (0, 0, 1)])


def test_singular_mass_names_the_dynamic_coordinates():
    m = _spatial()
    m.add_hinge("h", ("ground", "shaft"), axis=(1, 0, 0))
    m.make_dynamic("shaft.l1")  # the rotation about the axis: no inertia on the shaft
    with pytest.raises(InputError, match=r"singular mass matrix.*\['shaft.l1'\].*add_rigid_body"):
        m.compile()
    m.add_rigid_body("shaft", np.diag([0.0, 1.0, 1.0]))  # no inertia about the hinge axis either
    with pytest.raises(InputError, match="singular mass matrix"):
        m.compile()
    m.add_rigid_body("shaft", np.diag([0.5, 0.0, 0.0]))
    assert m.compile().n_dynamic == 1


def test_planar_and_spatial_calls_do_not_mix():
    m = _spatial()
    with pytest.raises(InputError, match="3-D position"):
        m.add_point("P", (0.0, 1.0))
    with pytest.raises(InputError, match="planar"):
        m.add_angle("phi")
    with pytest.raises(InputError, match="3-vector"):
        m.set_gravity((0.0, -9.81))
    with pytest.raises(InputError, match="spatial"):
        Model("p").add_orientation("R")
    with pytest.raises(InputError, match="dimension must be 2"):
        Model("q", dimension=4)
    with pytest.raises(InputError, match="rotation must be Euler parameters"):
        m.add_orientation("bad", rotation=np.diag([1.0, 1.0, -1.0]))


def test_hinge_torque_accelerates_a_shaft_by_torque_over_inertia():
    """A shaft on a free hinge about x with a resisting torque T: J theta'' = -T, so at rest
    lam_1'' = theta'' / 2 = -T / (2 J) makes the reduced residual vanish; at theta = 1 rad,
    theta' = 3 rad/s the rates follow lam = (cos(theta/2), sin(theta/2), 0, 0)."""
    from periodyn.model.linearization import reduced_residual
    J, T = 0.7, 2.5
    m = _spatial()
    m.add_hinge("h", ("ground", "shaft"), axis=(1, 0, 0), torque=T, damping=0.4)
    m.add_rigid_body("shaft", np.diag([J, 2.0, 3.0]))
    m.make_dynamic("shaft.l1")
    model = m.compile()
    np.testing.assert_allclose(reduced_residual(model, 0.0, [0.0], [0.0], [-T / (2 * J)], 0.0), 0, atol=1e-12)
    th, w = 1.0, 3.0
    acc = -(T + 0.4 * w) / J
    lam1 = np.sin(th / 2)
    lam1_dot = 0.5 * np.cos(th / 2) * w
    lam1_ddot = 0.5 * np.cos(th / 2) * acc - 0.25 * np.sin(th / 2) * w**2
    np.testing.assert_allclose(reduced_residual(model, 0.0, [lam1], [lam1_dot], [lam1_ddot], 0.0), 0, atol=1e-11)


def test_body_component_output_matches_twin_and_co_rotates():
    """A point carried by a turning shaft: its offset in the shaft's frame is constant, and
    the output's gradient equals the complex-step gradient of a NumPy twin."""
    from periodyn.kernels.mechanism.outputs import body_component
    from periodyn.model.kinematics import nominal_configurations
    from tests.twins.spatial_joints import complex_step, rotation_twin

    m = _spatial()
    m.add_hinge("h", ("ground", "shaft"), axis=(1, 0, 0))
    m.prescribe("h.rotation")
    m.add_point("A", (0.0, 0.0, 0.0))
    m.add_point("M", (0.5, 0.02, -0.01))
    m.fix("A")
    m.add_rigid_link("arm", ("A", "M"), "shaft")
    m.add_orientation("tip")
    m.fix("tip")
    m.add_hinge("twist", ("shaft", "tip"), axis=(1, 0, 0), misalignment="free")  # measures only
    m.add_body_component("lateral", ("A", "M"), "shaft", (0.0, 2.0, 0.0), scale=0.5)
    m.add_mode_output("twist_angle", "twist.rotation")
    model = m.compile()
    out, twist = model.outputs
    from periodyn.kernels.mechanism import assembly
    from periodyn.model.kinematics import motion
    tensors = assembly.allocate_tensors(model.arrays)
    for x in nominal_configurations(model, 5):  # the fixed tip turns by -theta relative to the shaft
        assembly.element_tensors(model.arrays, x, *tensors)
        v = motion(model, x, np.ones(1), np.zeros(1)).v
        assert twist.gradient(x, tensors[1]) @ v[twist.dofs] == pytest.approx(-1.0, abs=1e-13)
    d = np.array([0.0, 1.0, 0.0])
    twin = lambda xe: d @ rotation_twin(xe[3:7]).T @ (xe[7:10] - xe[0:3]) / 0.5  # noqa: E731
    for x in nominal_configurations(model, 5):
        grad = np.empty(10)
        assert body_component(x[out.dofs], out.direction, out.scale, grad) == pytest.approx(0.04, abs=1e-14)
        np.testing.assert_allclose(out.gradient(x), complex_step(twin, x[out.dofs]), atol=1e-14)
    xe = np.random.default_rng(3).standard_normal(10)
    grad = np.empty(10)
    assert body_component(xe, d, 0.5, grad) == pytest.approx(twin(xe), abs=1e-14)
    np.testing.assert_allclose(grad, complex_step(twin, xe), atol=1e-13)


def test_euler_parameters_of_any_rotation():
    """Round trip R -> lam -> R for random rotations and half-turns about each axis."""
    from periodyn.model.spatial import axis_angle
    rng = np.random.default_rng(5)
    lams = [rng.standard_normal(4) for _ in range(20)] + [axis_angle(np.eye(3)[i] + 1e-3, np.pi) for i in range(3)]
    for lam in lams:
        lam = lam / np.linalg.norm(lam)
        got = euler_parameters(rotation_of(lam))
        np.testing.assert_allclose(got, lam * np.sign(lam[0]) if lam[0] != 0 else lam, atol=1e-14)
