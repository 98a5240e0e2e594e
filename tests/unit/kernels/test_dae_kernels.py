"""Rigid-body kernels against plain-NumPy twins and finite differences; IHB building blocks."""

import numpy as np
import pytest

from periodyn.nonlinear.ihb_fourier import complex_to_real, derivative_matrix, product_blocks, real_coefficients, real_samples, real_to_complex
from periodyn.nonlinear.ihb_solver import IHBProblem
from periodyn.examples.dae_examples import duffing, inverted_pendulum, rod_pendulum, slider_chain_pendulum, slider_rod_pendulum

RNG = np.random.default_rng(7)


def _rot(phi):
    return np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])


def _chain_phi_numpy(q, t, w, n_rods, l, p):
    """Plain-NumPy twin of the slider-chain constraints (eq. 80 with the slider joint)."""
    out = [q[1]]
    r_prev, phi_prev = q[0:2], None
    for i in range(n_rods):
        c = 2 + 3 * i
        r, phi = q[c:c + 2], q[c + 2]
        a = r_prev if phi_prev is None else r_prev + _rot(phi_prev) @ np.array([l / 2, 0.0])
        out += list(r + _rot(phi) @ np.array([-l / 2, 0.0]) - a)
        r_prev, phi_prev = r, phi
    return np.array(out)


@pytest.fixture(scope="module")
def chain():
    return slider_chain_pendulum(n_rods=4)


def _random_state(sysm, scale=0.3):
    q = sysm.q0 + scale * RNG.standard_normal(sysm.n)
    qd = RNG.standard_normal(sysm.n)
    return q, qd


def test_chain_constraints_match_numpy_twin(chain):
    q, _ = _random_state(chain)
    t = np.array([0.37])
    got = chain.constraint(q[None], t, 3.0, chain.parameters)[0]
    want = _chain_phi_numpy(q, 0.37, 3.0, 4, 0.025, 1.0)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-14)


@pytest.mark.parametrize("build", [rod_pendulum, inverted_pendulum, slider_rod_pendulum, lambda: slider_chain_pendulum(4)])
def test_constraint_derivatives_against_finite_differences(build):
    s = build()
    P = s.parameters
    q, qd = _random_state(s)
    t, w, h = np.array([0.21]), 2.3, 1e-6
    Pq = s.constraint_jacobian(q[None], t, w, P)[0]
    fd = np.stack([(s.constraint((q + h * e)[None], t, w, P)[0] - s.constraint((q - h * e)[None], t, w, P)[0]) / (2 * h)
                   for e in np.eye(s.n)], axis=1)
    np.testing.assert_allclose(Pq, fd, atol=1e-8)
    lam = RNG.standard_normal(s.m)
    Hl = s.constraint_hessian(q[None], lam[None], t, w, P)[0]
    fdh = np.stack([(s.constraint_jacobian((q + h * e)[None], t, w, P)[0] - s.constraint_jacobian((q - h * e)[None], t, w, P)[0]).T
                    @ lam / (2 * h) for e in np.eye(s.n)], axis=1)
    np.testing.assert_allclose(Hl, fdh, atol=1e-7)
    # Phi_t and gamma: along q(t) = q + qd (t - t0) + a (t - t0)^2/2, d^2 Phi/dt^2 = Phi_q a - gamma
    phit, gam = s.constraint_rates(q[None], qd[None], t, w, P)
    a = RNG.standard_normal(s.n)
    ht = 1e-4

    def phi_at(dt):
        return s.constraint((q + qd * dt + 0.5 * a * dt * dt)[None], t + dt, w, P)[0]

    d1 = (phi_at(ht) - phi_at(-ht)) / (2 * ht)
    d2 = (phi_at(ht) - 2 * phi_at(0.0) + phi_at(-ht)) / ht ** 2
    np.testing.assert_allclose(d1, Pq @ qd + phit[0], atol=1e-7)
    np.testing.assert_allclose(d2, Pq @ a - gam[0], atol=2e-5)


@pytest.mark.parametrize("build", [rod_pendulum, inverted_pendulum, slider_rod_pendulum, lambda: slider_chain_pendulum(4), duffing])
def test_force_jacobians_against_finite_differences(build):
    s = build()
    P = s.parameters
    q, qd = _random_state(s)
    t, w, h = np.array([0.4]), 1.7, 1e-6
    Kq, Kv = (a[0] for a in s.force_jacobians(q[None], qd[None], t, w, P))
    f = lambda qq, vv: s.force(qq[None], vv[None], t, w, P)[0]
    fdq = np.stack([(f(q + h * e, qd) - f(q - h * e, qd)) / (2 * h) for e in np.eye(s.n)], axis=1)
    fdv = np.stack([(f(q, qd + h * e) - f(q, qd - h * e)) / (2 * h) for e in np.eye(s.n)], axis=1)
    np.testing.assert_allclose(Kq, fdq, atol=1e-6 * max(1, np.abs(fdq).max()))
    np.testing.assert_allclose(Kv, fdv, atol=1e-7)


def test_real_complex_layout_round_trip_and_derivative():
    H, p = 4, 27
    a = RNG.standard_normal((2 * H + 1, 3))
    np.testing.assert_allclose(complex_to_real(real_to_complex(a), H), a, atol=1e-15)
    x = real_samples(a, p)
    tau = 2 * np.pi * np.arange(p) / p
    k = np.arange(1, H + 1)
    direct = a[0] + np.cos(np.outer(tau, k)) @ a[1:H + 1] + np.sin(np.outer(tau, k)) @ a[H + 1:]
    np.testing.assert_allclose(x, direct, atol=1e-13)
    np.testing.assert_allclose(real_coefficients(x, H), a, atol=1e-13)
    dd = -np.sin(np.outer(tau, k)) @ (k[:, None] * a[1:H + 1]) + np.cos(np.outer(tau, k)) @ (k[:, None] * a[H + 1:])
    np.testing.assert_allclose(real_samples(derivative_matrix(H) @ a, p), dd, atol=1e-12)


def test_product_blocks_equal_galerkin_quadrature():
    """G @ x equals the Fourier coefficients of A(tau) x(tau), computed on a fine grid."""
    H, p = 3, 13
    A_coef = RNG.standard_normal((2 * 2 * H + 1, 2))  # A with 2H harmonics: exactly resolved
    A = real_samples(A_coef, p)
    G = product_blocks(A, H)
    x = RNG.standard_normal((2 * H + 1,))
    fine = 401
    prod = real_samples(A_coef, fine) * real_samples(x[:, None], fine)
    for e in range(2):
        np.testing.assert_allclose(G[e] @ x, real_coefficients(prod[:, e], H), atol=1e-12)


@pytest.mark.parametrize("build,omega", [(duffing, 1.3), (rod_pendulum, 3.0), (inverted_pendulum, 9.0),
                                         (slider_rod_pendulum, 6.0), (lambda: slider_chain_pendulum(3), 4.0)])
def test_ihb_jacobian_against_finite_differences(build, omega):
    s = build()
    for dense in (True, False):
        prob = IHBProblem(s, 3, dense=dense)
        X = prob.initial(omega=omega) + 0.03 * np.random.default_rng(3).standard_normal(prob.size)
        R, J = prob.residual_jacobian(X, omega)
        h = 1e-6
        fd = np.stack([(prob.residual(X + h * e, omega) - prob.residual(X - h * e, omega)) / (2 * h)
                       for e in np.eye(prob.size)], axis=1)
        np.testing.assert_allclose(J if dense else J.toarray(), fd, atol=1e-7 * max(1.0, np.abs(fd).max()))
