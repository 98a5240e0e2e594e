"""The IHB Jacobian on its fixed, banded block pattern against a plain dense-block assembly
(every non-zero entry pair a full (2H+1)^2 block of FFT product coefficients), its growth when
an orbit needs more, and the solve through the kept fill-reducing ordering."""

import numpy as np
import pytest

from periodyn.nonlinear import ihb
from periodyn.nonlinear.ihb_fourier import product_blocks
from periodyn.nonlinear.ihb_solver import IHBProblem
from periodyn.examples.dae_examples import duffing, rod_pendulum, slider_chain_pendulum, slider_rod_pendulum
from periodyn.numerics.newton_iteration import lu_factor

RNG = np.random.default_rng(12)


def dense_block_jacobian(prob, X, omega):
    """Twin: J from full blocks G(K) + G(C) D + G(M) D^2 and G(Phi_q) for every non-zero pair."""
    s, P = prob.system, prob.system.parameters
    L, n, H = prob.L, prob.n, prob.H
    t, q, qd, qdd, lam = prob.time_samples(X, omega)
    Kf, Cf = s.force_jacobians(q, qd, t, omega, P)
    Kt = -Kf + (s.constraint_hessian(q, lam, t, omega, P) if s.m else 0)
    M = np.asarray(s.mass(q))
    D1 = omega / prob.nu * prob.D
    A = np.zeros((prob.size, prob.size))
    for i, j in zip(*np.nonzero(np.any(Kt != 0, 0) | np.any(Cf != 0, 0) | np.any(M != 0, 0))):
        G = product_blocks(np.stack([Kt[:, i, j], -Cf[:, i, j], M[:, i, j]], 1), H)
        A[i * L:(i + 1) * L, j * L:(j + 1) * L] = G[0] + G[1] @ D1 + G[2] @ D1 @ D1
    if s.m:
        Pq = s.constraint_jacobian(q, t, omega, P)
        for k, j in zip(*np.nonzero(np.any(Pq != 0, 0))):
            G = product_blocks(Pq[:, k, j][:, None], H)[0]
            A[j * L:(j + 1) * L, (n + k) * L:(n + k + 1) * L] = G
            A[(n + k) * L:(n + k + 1) * L, j * L:(j + 1) * L] = G
    return A


@pytest.mark.parametrize("build,omega", [(duffing, 1.3), (rod_pendulum, 3.0), (slider_rod_pendulum, 6.0),
                                         (lambda: slider_chain_pendulum(4), 4.0)])
def test_pattern_jacobian_equals_the_dense_block_assembly_and_grows_when_needed(build, omega):
    s = build()
    prob = IHBProblem(s, 5, dense=False)
    X0 = prob.initial(omega=omega)
    J0 = prob.residual_jacobian(X0, omega)[1]  # constant orbit: diagonal and band-0 blocks only
    np.testing.assert_allclose(J0.toarray(), dense_block_jacobian(prob, X0, omega), rtol=0, atol=1e-12 * abs(J0).max())
    narrow = prob._pattern
    X = X0 + 0.05 * RNG.standard_normal(prob.size)
    R, J = prob.residual_jacobian(X, omega)
    A = dense_block_jacobian(prob, X, omega)
    # a random orbit has every harmonic: the pattern was rebuilt larger, nothing is lost
    assert prob._pattern is not narrow and np.all(prob._pattern.reach >= narrow.reach)
    np.testing.assert_allclose(J.toarray(), A, rtol=0, atol=1e-12 * np.abs(A).max())
    assert prob.residual_jacobian(X, omega)[1].fill_ordering is J.fill_ordering  # the same pattern is kept
    np.testing.assert_allclose(lu_factor(J)(R), np.linalg.solve(A, R), rtol=1e-9, atol=1e-12)


def test_blocks_are_harmonic_bands_on_a_small_orbit():
    """On the chain's slow small-amplitude orbit the varying entries reach only a few
    harmonics: the stored Jacobian keeps those bands (fewer entries than full blocks) and
    still equals the dense assembly."""
    s = slider_chain_pendulum(4)
    prob = IHBProblem(s, 8, dense=False)
    sol = ihb(s, 2.0, 8, stability=None)
    X = prob.from_solution(sol)
    J = prob.residual_jacobian(X, 2.0)[1]
    A = dense_block_jacobian(prob, X, 2.0)
    reach = prob._pattern.reach
    assert 0 <= reach.max() < 2 * prob.H
    np.testing.assert_allclose(J.toarray(), A, rtol=0, atol=1e-12 * np.abs(A).max())


@pytest.mark.parametrize("build,omega", [(duffing, 1.3), (rod_pendulum, 3.0), (slider_rod_pendulum, 6.0),
                                         (lambda: slider_chain_pendulum(3), 4.0)])
def test_dense_jacobian_of_small_problems_equals_the_block_assembly(build, omega):
    """Small problems get a dense Jacobian (Galerkin matrices of the samples, no FFT): the
    FFT block twin gives the same matrix, and the residual is the same as the sparse path's."""
    s = build()
    prob = IHBProblem(s, 5)
    assert prob.dense and prob.size <= 200
    X = prob.initial(omega=omega) + 0.05 * RNG.standard_normal(prob.size)
    R, J = prob.residual_jacobian(X, omega)
    A = dense_block_jacobian(prob, X, omega)
    assert isinstance(J, np.ndarray)
    np.testing.assert_allclose(J, A, rtol=0, atol=1e-12 * np.abs(A).max())
    np.testing.assert_allclose(R, IHBProblem(s, 5, dense=False).residual(X, omega), rtol=0, atol=1e-14)
