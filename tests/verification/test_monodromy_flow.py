"""The one monodromy (timedomain.monodromy_matrix, the variational flow of
nonlinear.variational) against closed forms: the matrix exponential of a constant-
coefficient system, and Floquet's theorem for a system given by exact callables."""

import numpy as np
from scipy.linalg import expm

from periodyn import RheoLinear
from periodyn.timedomain import monodromy_matrix


def test_constant_coefficients_give_the_matrix_exponential():
    M = np.array([[2.0, 0.3], [0.3, 1.0]])
    C = np.array([[0.4, -0.1], [-0.1, 0.2]])
    K = np.array([[50.0, -10.0], [-10.0, 30.0]])
    omega = 3.0
    system = RheoLinear.from_samples(np.broadcast_to(M, (9, 2, 2)), C, K, np.array([1.0, -2.0]), omega)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    ref = expm(A * 2 * np.pi / omega)
    np.testing.assert_allclose(monodromy_matrix(system), ref, rtol=0, atol=1e-9 * np.abs(ref).max())


def test_exact_callables_are_used():
    """q'' + (1 + 0.5 sign(cos t)) q = 0 (Meissner), whose coefficient is not band-limited:
    the monodromy is the product of the two constant-stiffness half-period flows."""
    omega = 1.0

    def k(t):
        return 1.0 + 0.5 * np.sign(np.cos(omega * t))

    system = RheoLinear.from_functions(lambda t: 1.0, lambda t: 0.0, k, lambda t: 0.0, omega, 33)

    def flow(kk, span):
        return expm(np.array([[0.0, 1.0], [-kk, 0.0]]) * span)

    T = 2 * np.pi / omega
    ref = flow(1.5, T / 4) @ flow(0.5, T / 2) @ flow(1.5, T / 4)
    np.testing.assert_allclose(monodromy_matrix(system), ref, rtol=0, atol=1e-6)
