"""periodyn.DAE construction from user callables: defaults and refusals."""

import math

import numpy as np
import pytest

from periodyn.dae import DAE
from periodyn.errors import InputError


def _force(q, qd, t, w):
    return -q - 0.1 * qd + np.cos(w * t)


def test_constraint_without_complex_support_needs_its_jacobian():
    with pytest.raises(InputError, match="constraint_jacobian"):
        DAE(np.eye(2), _force, lambda q, t, w: np.array([math.cos(float(q[0])) - q[1]]))


def test_constraint_jacobian_derived_by_complex_step_equals_the_analytic_one():
    """Rod pendulum written without constraint_jacobian: Phi_q by the complex step equals the
    analytic Jacobian to round-off, the Hessian term (central differences of it) to 1e-9,
    and IHB gives the same orbit as the builder's analytic kernels."""
    from periodyn.nonlinear import ihb
    from periodyn.examples.dae_examples import rod_pendulum

    def force(q, qd, t, w):
        return np.array([0.0 * q[0], -9.81 + 0.0 * q[1], -0.04 * qd[2] + 0.15 * np.cos(w * t)])

    def phi(q, t, w):
        return np.array([q[0] - 0.5 * np.cos(q[2]), q[1] - 0.5 * np.sin(q[2])])

    s = DAE(np.diag([1.0, 1.0, 1 / 12]), force, phi, q0=[0, -0.5, -np.pi / 2])
    ref = rod_pendulum()
    rng = np.random.default_rng(5)
    q, lam, t = rng.standard_normal((4, 3)), rng.standard_normal((4, 2)), rng.random(4)
    analytic = np.stack([[[1, 0, 0.5 * np.sin(x[2])], [0, 1, -0.5 * np.cos(x[2])]] for x in q])
    np.testing.assert_allclose(s.constraint_jacobian(q, t, 2.0, {}), analytic, rtol=0, atol=1e-15)
    np.testing.assert_allclose(s.constraint_hessian(q, lam, t, 2.0, {}), ref.constraint_hessian(q, lam, t, 2.0, ref.parameters),
                               rtol=0, atol=1e-9)
    a, b = ihb(s, 3.0, 6), ihb(ref, 3.0, 6)
    np.testing.assert_allclose(a.harmonics, b.harmonics, atol=1e-12)
    np.testing.assert_allclose(a.multipliers, b.multipliers, atol=1e-9)


def test_time_dependent_constraint_needs_rates():
    with pytest.raises(InputError, match="constraint_rates"):
        DAE(np.eye(2), _force, lambda q, t, w: np.array([q[0] - np.sin(w * t)]),
            constraint_jacobian=lambda q, t, w: np.array([[1.0, 0.0]]))


def test_force_without_complex_support_needs_a_jacobian():
    def real_only(q, qd, t, w):
        return np.array([-math.sin(float(q[0]))])

    with pytest.raises(InputError, match="force_jacobian"):
        DAE(np.eye(1), real_only)


def test_complex_step_defaults_equal_analytic_derivatives():
    def force(q, qd, t, w, P):
        return np.array([-P["k"] * np.sin(q[0]) * q[1] - qd[0] * qd[1], -q[1] ** 3 + np.cos(w * t)])

    def phi(q, t, w, P):
        return np.array([q[0] ** 2 + np.sin(q[1]) - 1.0])

    def phi_q(q, t, w, P):
        return np.array([[2 * q[0], np.cos(q[1])]])

    s = DAE(np.eye(2), force, phi, constraint_jacobian=phi_q, parameters={"k": 2.0}, q0=[0.5, 0.3])
    q, qd = np.array([[0.4, 0.7]]), np.array([[0.3, -0.2]])
    Kq, Kv = s.force_jacobians(q, qd, np.zeros(1), 1.0, s.parameters)
    np.testing.assert_allclose(Kq[0], [[-2 * np.cos(0.4) * 0.7, -2 * np.sin(0.4)], [0.0, -3 * 0.49]], atol=1e-14)
    np.testing.assert_allclose(Kv[0], [[0.2, -0.3], [0.0, 0.0]], atol=1e-14)
    H = s.constraint_hessian(q, np.array([[1.5]]), np.zeros(1), 1.0, s.parameters)
    np.testing.assert_allclose(H[0], [[3.0, 0.0], [0.0, -1.5 * np.sin(0.7)]], atol=1e-14)
    _, gamma = s.constraint_rates(q, qd, np.zeros(1), 1.0, s.parameters)
    np.testing.assert_allclose(gamma[0], [-(2 * 0.09 - np.sin(0.7) * 0.04)], atol=1e-14)
    assert s.with_parameters(k=3.0).parameters["k"] == 3.0 and s.parameters["k"] == 2.0


def test_vectorized_force_equals_the_per_point_one_and_its_jacobians():
    """A force declared vectorized (one call over all samples) gives the per-point force's
    values and, by the stacked complex step or the given batch Jacobian, its derivatives."""
    def point(q, qd, t, w, P):
        return np.array([-P["k"] * np.sin(q[0]) * q[1] - qd[0] * qd[1], -q[1] ** 3 + np.cos(w * t)])

    def batch(q, qd, t, w, P):
        return np.stack([-P["k"] * np.sin(q[:, 0]) * q[:, 1] - qd[:, 0] * qd[:, 1], -q[:, 1] ** 3 + np.cos(w * t)], 1)

    def batch_jac(q, qd, t, w, P):
        z = np.zeros(len(t))
        Kq = np.stack([np.stack([-P["k"] * np.cos(q[:, 0]) * q[:, 1], -P["k"] * np.sin(q[:, 0])], -1),
                       np.stack([z, -3 * q[:, 1] ** 2], -1)], 1)
        Kv = np.stack([np.stack([-qd[:, 1], -qd[:, 0]], -1), np.stack([z, z], -1)], 1)
        return Kq, Kv

    rng = np.random.default_rng(4)
    q, qd, t = rng.standard_normal((7, 2)), rng.standard_normal((7, 2)), rng.random(7)
    ref = DAE(np.eye(2), point, parameters={"k": 2.0})
    for s in (DAE(np.eye(2), batch, parameters={"k": 2.0}, vectorized=True),
              DAE(np.eye(2), batch, force_jacobian=batch_jac, parameters={"k": 2.0}, vectorized=True)):
        np.testing.assert_allclose(s.force(q, qd, t, 1.3, s.parameters), ref.force(q, qd, t, 1.3, ref.parameters),
                                   rtol=0, atol=1e-14)
        pairs = zip(s.force_jacobians(q, qd, t, 1.3, s.parameters), ref.force_jacobians(q, qd, t, 1.3, ref.parameters))
        for a, b in pairs:
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-13)
    with pytest.raises(InputError, match="vectorized"):
        DAE(np.eye(2), point, parameters={"k": 2.0}, vectorized=True)
