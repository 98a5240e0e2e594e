"""IHBProblem.omega_derivative (the continuation's dR/domega with the samples taken once)
against the central difference of the full residual, and the orbit state matrices of a
non-unit mass against the linearized orbit's monodromy."""

import numpy as np
import pytest

import periodyn
from periodyn.nonlinear.ihb_solver import IHBProblem


def duffing(mass=1.0):
    def force(q, qd, t, w):
        return -0.05 * qd - q - 0.1 * q ** 3 + 0.18 * np.cos(w * t)[:, None]

    def jac(q, qd, t, w):
        return (-1.0 - 0.3 * q ** 2)[:, :, None], np.full((len(t), 1, 1), -0.05)

    return periodyn.DAE(mass * np.eye(1), force, force_jacobian=jac, vectorized=True)


@pytest.mark.parametrize("nu", [1, 2])
def test_omega_derivative_matches_residual_difference(nu):
    prob = IHBProblem(duffing(), 5, subharmonic=nu)
    X = np.random.default_rng(3).normal(size=prob.size)
    w, h = 1.3, 1.3e-6
    ref = (prob.residual(X, w + h) - prob.residual(X, w - h)) / (2 * h)
    assert np.allclose(prob.omega_derivative(X, w, h), ref, rtol=1e-7, atol=1e-9 * np.abs(ref).max())


def test_omega_derivative_of_a_constrained_dae():
    """A pendulum in Cartesian coordinates (x, y) with its length constraint, driven at its pivot."""
    def force(q, qd, t, w):
        return np.array([0.2 * np.cos(w * t) - 0.01 * qd[0], -9.81 - 0.01 * qd[1]])

    s = periodyn.DAE(np.eye(2), force, constraint=lambda q, t, w: np.array([q[0] ** 2 + q[1] ** 2 - 1.0]),
                     q0=np.array([0.0, -1.0]))
    prob = IHBProblem(s, 4)
    X = 0.1 * np.random.default_rng(5).normal(size=prob.size)
    w, h = 2.0, 2e-6
    ref = (prob.residual(X, w + h) - prob.residual(X, w - h)) / (2 * h)
    assert np.allclose(prob.omega_derivative(X, w, h), ref, rtol=1e-7, atol=1e-9 * np.abs(ref).max())


def test_state_generator_with_a_non_unit_mass():
    """m = 2: the flow of "auto" agrees with DOP853 on the linearized orbit."""
    s = duffing(2.0)
    sol = periodyn.ihb(s, 0.7, 7, stability=None)
    prob = IHBProblem(s, 7)
    X = prob.from_solution(sol)
    fl, ref = prob.exponents(X, 0.7, None, "auto"), prob.exponents(X, 0.7, None, "monodromy")
    assert "flow" in fl.reason
    assert np.allclose(np.sort(np.abs(fl.multipliers)), np.sort(np.abs(ref.multipliers)), rtol=1e-8)


@pytest.mark.parametrize("nu", [1, 2])
def test_chain_rule_after_the_jacobian_matches_the_difference(nu):
    """Right after the Jacobian at the same point (the corrector's order), the chain-rule path;
    a force with an explicit omega dependence (unbalance omega^2 cos(omega t)) and a q'-dependent
    damping exercise both of its parts."""
    def force(q, qd, t, w):
        return -0.05 * qd * (1 + q ** 2) - q - 0.1 * q ** 3 + 0.02 * w ** 2 * np.cos(w * t)[:, None]

    s = periodyn.DAE(np.array([[1.5]]), force, vectorized=True)
    prob = IHBProblem(s, 5, subharmonic=nu)
    X = 0.3 * np.random.default_rng(7).normal(size=prob.size)
    w, h = 1.1, 1.1e-6
    ref = (prob.residual(X, w + h) - prob.residual(X, w - h)) / (2 * h)
    prob.residual_jacobian(X, w)
    assert prob._last is not None
    assert np.allclose(prob.omega_derivative(X, w, h), ref, rtol=1e-7, atol=1e-8 * np.abs(ref).max())
    prob.residual_jacobian(X + 1e-3, w)  # another point: the difference path again
    assert np.allclose(prob.omega_derivative(X, w, h), ref, rtol=1e-7, atol=1e-8 * np.abs(ref).max())


def test_state_generator_reuses_the_last_jacobian_samples():
    s = duffing(2.0)
    prob = IHBProblem(s, 5)
    X = 0.3 * np.random.default_rng(11).normal(size=prob.size)
    fresh = prob.state_generator(X, 0.9).samples
    prob.residual_jacobian(X, 0.9)
    assert prob._at_last(X, 0.9, s.parameters) is not None
    assert np.array_equal(prob.state_generator(X, 0.9).samples, fresh)
    assert prob._at_last(X, 0.91, s.parameters) is None


def test_unit_mass_generator_gathers_the_varying_entries():
    """A two-mass cubic chain with unit mass: the generator built from the varying entries of
    the force Jacobians has the full state matrices [[0, I], [df/dq, df/dq']] as samples."""
    K, C = np.array([[2.0, -1.0], [-1.0, 2.0]]), np.array([[0.06, -0.01], [-0.01, 0.05]])

    def force(q, qd, t, w):
        return -qd @ C.T - q @ K.T - 0.1 * q ** 3 + 0.2 * np.cos(w * t)[:, None] * np.array([1.0, 0.0])

    s = periodyn.DAE(np.eye(2), force, vectorized=True)
    prob = IHBProblem(s, 5)
    X = prob.from_solution(periodyn.ihb(s, 1.1, 5, stability=None))
    gen = prob.state_generator(X, 1.1)
    t, q, qd, _, _ = prob.time_samples(X, 1.1)
    Kf, Cf = s.force_jacobians(q, qd, t, 1.1, s.parameters)
    full = np.zeros((prob.p, 4, 4))
    full[:, [0, 1], [2, 3]] = 1.0
    full[:, 2:, :2], full[:, 2:, 2:] = Kf, Cf
    assert np.array_equal(gen.samples, full)
    assert sorted(gen.varying) == [8, 13]  # the diagonal of df/dq: the cubic springs
