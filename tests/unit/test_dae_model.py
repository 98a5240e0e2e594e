"""periodyn.DAE construction from user callables: defaults and refusals."""

import math

import numpy as np
import pytest

from periodyn.dae import DAE
from periodyn.errors import InputError


def _force(q, qd, t, w):
    return -q - 0.1 * qd + np.cos(w * t)


def test_constraint_needs_its_jacobian():
    with pytest.raises(InputError, match="constraint_jacobian"):
        DAE(np.eye(2), _force, lambda q, t, w: np.array([q[0] - q[1]]))


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
