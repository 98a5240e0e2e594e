"""kernels.saddle against plain-NumPy twins, and the acceleration Jacobians against finite
differences of the accelerations."""

import numpy as np
import pytest

from periodyn.examples.dae_examples import duffing, inverted_pendulum, slider_rod_pendulum
from periodyn.kernels.solvers.saddle import saddle_accelerations, saddle_jacobians
from periodyn.numerics.integration import accelerations
from periodyn.numerics.variational import acceleration_jacobians


def random_case(p=3, n=5, m=2, seed=1):
    rng = np.random.default_rng(seed)
    R = rng.standard_normal((p, n, n))
    M = R @ np.swapaxes(R, 1, 2) + n * np.eye(n)
    H = rng.standard_normal((p, m, n, n))
    H = H + np.swapaxes(H, 2, 3)
    arrays = dict(M=M, f=rng.standard_normal((p, n)), Pq=rng.standard_normal((p, m, n)), phi=rng.standard_normal((p, m)),
                  phit=rng.standard_normal((p, m)), gam=rng.standard_normal((p, m)), qd=rng.standard_normal((p, n)),
                  Kq=rng.standard_normal((p, n, n)), Kv=rng.standard_normal((p, n, n)), H=H,
                  dphit=rng.standard_normal((p, m, 2 * n)), dgam=rng.standard_normal((p, m, 2 * n)))
    return arrays, 3.7


def twin(c, a):
    """NumPy twin of both kernels."""
    p, n = c["f"].shape
    A = np.zeros((p, n + 2, n + 2))
    A[:, :n, :n] = c["M"]
    A[:, :n, n:] = np.swapaxes(c["Pq"], 1, 2)
    A[:, n:, :n] = c["Pq"]
    rc = c["gam"] - 2 * a * (np.einsum("pkn,pn->pk", c["Pq"], c["qd"]) + c["phit"]) - a * a * c["phi"]
    x = np.linalg.solve(A, np.concatenate([c["f"], rc], axis=1)[..., None])[..., 0]
    qdd = x[:, :n]
    G_a = np.einsum("pkij,pj->pki", c["H"], qdd)
    G_v = np.einsum("pkij,pj->pki", c["H"], c["qd"])
    c_q = c["dgam"][..., :n] - 2 * a * (G_v + c["dphit"][..., :n]) - a * a * c["Pq"] - G_a
    c_v = c["dgam"][..., n:] - 2 * a * (c["Pq"] + c["dphit"][..., n:])
    B = np.concatenate([np.concatenate([c["Kq"], c["Kv"]], axis=2), np.concatenate([c_q, c_v], axis=2)], axis=1)
    D = np.linalg.solve(A, B)[:, :n]
    return x, D[:, :, :n], D[:, :, n:]


def test_saddle_kernels_match_numpy_twin():
    c, a = random_case()
    p, n = c["f"].shape
    x, Ai = np.empty((p, n + 2)), np.empty((p, n + 2, n + 2))
    saddle_accelerations(c["M"], c["f"], c["Pq"], c["phi"], c["phit"], c["gam"], c["qd"], a, x, Ai)
    D = np.empty((p, n, 2 * n))
    saddle_jacobians(Ai, c["Kq"], c["Kv"], c["H"], x[:, :n], c["qd"], c["Pq"], c["dphit"], c["dgam"], a, D)
    x2, Aq2, Av2 = twin(c, a)
    for got, want in ((x, x2), (D[:, :, :n], Aq2), (D[:, :, n:], Av2)):
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())


@pytest.mark.parametrize("system", [duffing(), inverted_pendulum(), slider_rod_pendulum()], ids=lambda s: s.name)
def test_acceleration_jacobians_match_finite_differences(system):
    n, rng = system.n, np.random.default_rng(0)
    q, qd = system.q0 + 0.1 * rng.standard_normal(n), 0.3 * rng.standard_normal(n)
    t, w, a, P = np.array([0.37]), 2.0, 10.0, system.parameters
    qdd, Aq, Av = acceleration_jacobians(system, q[None], qd[None], t, w, P, a)
    np.testing.assert_allclose(qdd[0], accelerations(system, q[None], qd[None], t, w, P, a)[0][0], rtol=1e-12, atol=1e-12)
    h, J = 1e-6, np.zeros((n, 2 * n))
    for j in range(2 * n):
        e = np.zeros(2 * n)
        e[j] = h
        up = accelerations(system, (q + e[:n])[None], (qd + e[n:])[None], t, w, P, a)[0]
        down = accelerations(system, (q - e[:n])[None], (qd - e[n:])[None], t, w, P, a)[0]
        J[:, j] = (up - down)[0] / (2 * h)
    np.testing.assert_allclose(np.hstack([Aq[0], Av[0]]), J, atol=1e-7 * max(1.0, np.abs(J).max()))
