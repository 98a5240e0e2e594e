"""The one monodromy (timedomain.monodromy_matrix, the variational flow of
nonlinear.variational) against closed forms: the matrix exponential of a constant-
coefficient system, and Floquet's theorem for a system given by exact callables."""

import numpy as np
from scipy.linalg import expm

from periodyn import RheoLinear
from periodyn.stability.monodromy import monodromy_matrix


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


def test_coefficients_at_a_time_are_the_fourier_sums_of_the_spectra():
    """The one real product of the stacked spectra (timedomain._coefficients) against the
    definition: the real part of sum_l X_l exp(i l omega t), l = -L..L, for M, C, K and f."""
    from periodyn.stability.monodromy import _coefficients

    rng = np.random.default_rng(7)
    p, n, omega = 13, 3, 2.5
    theta = 2 * np.pi * np.arange(p) / p
    M = np.eye(n) * (2 + 0.3 * np.cos(theta))[:, None, None] + 0.05 * rng.standard_normal((p, n, n))
    system = RheoLinear.from_samples(M, rng.standard_normal((p, n, n)), rng.standard_normal((p, n, n)),
                                     rng.standard_normal((p, n)), omega)
    S = system.spectra
    L = (S.mass.shape[0] - 1) // 2
    at, free = _coefficients(system), _coefficients(system, forced=False)
    for t in rng.uniform(0, 10, 5):
        e = np.exp(1j * np.arange(-L, L + 1) * omega * t)
        ref = [np.tensordot(e, X, 1).real for X in (S.mass, S.damping, S.stiffness, S.force)]
        for got in (at(t), free(t) + (ref[3],)):
            for x, r in zip(got, ref):
                np.testing.assert_allclose(x, r, rtol=0, atol=1e-13 * np.abs(r).max())


def test_the_flow_keeps_only_the_end_state(monkeypatch):
    """The monodromy's integration keeps the end state, not every step: a stiff model takes
    hundreds of thousands of explicit steps, each holding the 2n (2n + 1) variational
    states (the 16-element slider-crank filled 7.6 GB in five minutes)."""
    from periodyn.numerics import variational

    kept = []
    solve = variational.solve

    def recording(*args, **kwargs):
        sol = solve(*args, **kwargs)
        kept.append((sol.y.shape[1], sol.nfev))
        return sol

    monkeypatch.setattr(variational, "solve", recording)
    K = np.array([[400.0, -100.0], [-100.0, 300.0]])
    system = RheoLinear.from_samples(np.broadcast_to(np.eye(2), (9, 2, 2)), 0.01 * K, K, np.zeros(2), 1.0)
    monodromy_matrix(system)
    (stored, evaluations), = kept
    assert stored == 1 and evaluations > 100  # many steps, one state kept
