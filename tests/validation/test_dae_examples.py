"""Ju, Fan & Zhu (2021), App. B: the four example DAEs in the form of eqs. (61)-(82).

Sources: seed paper appendix B (parameter values lost; ours are in sweeps/dae_*.toml).
"""

import inspect
import pathlib
import tomllib

import numpy as np
import pytest

from periodyn.examples import dae_examples as ex

SWEEPS = pathlib.Path(__file__).resolve().parents[2] / "sweeps"
NAMES = ["rod_pendulum", "inverted_pendulum", "slider_rod_pendulum", "slider_chain_pendulum"]


@pytest.mark.parametrize("name", NAMES)
def test_sweep_files_hold_the_builder_defaults(name):
    cfg = tomllib.loads((SWEEPS / f"dae_{name}.toml").read_text())
    assert cfg["model"]["example"] == name
    defaults = {k: v.default for k, v in inspect.signature(getattr(ex, name)).parameters.items()}
    assert cfg["model"]["parameters"] == defaults


def test_sizes_of_the_41_body_chain():
    s = ex.slider_chain_pendulum()
    assert (s.n, s.m) == (122, 81)
    phi = s.constraint(s.q0[None], np.zeros(1), 1.0, s.parameters)[0]
    assert np.abs(phi).max() < 1e-15  # q0 is the hanging chain


def _potential(q, n_rods, m1, m, l, kappa1, kappa_hat, g=9.81):
    """Eq. (72): V = m1 g y1 + kappa1 x1^2/2 + sum m g y_i + kappa_hat/2 [(-pi/2 - phi2)^2 + sum (phi_{i-1} - phi_i)^2]."""
    phis = q[4::3]
    ys = q[3::3]
    return (m1 * g * q[1] + 0.5 * kappa1 * q[0] ** 2 + m * g * ys.sum()
            + 0.5 * kappa_hat * ((-np.pi / 2 - phis[0]) ** 2 + np.sum(np.diff(phis) ** 2)))


def _dissipation_force(qd, n_rods, eps1, eps_hat):
    """-dD/dq' with the Rayleigh function D = eps1 x1'^2/2 + eps_hat/2 [phi2'^2 + sum (phi_i' - phi_{i-1}')^2]."""
    out = np.zeros_like(qd)
    out[0] = -eps1 * qd[0]
    w = qd[4::3]
    dw = np.diff(w)
    g = np.zeros_like(w)
    g[0] += eps_hat * w[0]
    g[:-1] -= eps_hat * dw
    g[1:] += eps_hat * dw
    out[4::3] = -g
    return out


def test_chain_forces_derive_from_energies_and_rayleigh_dissipation():
    """Our forces equal -dV/dq - dD/dq' (eqs. 71-74); the printed eqs. (77)-(78) have the opposite sign."""
    n_rods, pars = 5, dict(m1=1.0, m=0.025, l=0.025, kappa1=100.0, kappa_hat=0.05)
    s = ex.slider_chain_pendulum(n_rods, p=0.0)
    rng = np.random.default_rng(3)
    q = s.q0 + 0.2 * rng.standard_normal(s.n)
    qd = rng.standard_normal(s.n)
    h = 1e-6
    gradV = np.array([(_potential(q + h * e, n_rods, **pars) - _potential(q - h * e, n_rods, **pars)) / (2 * h)
                      for e in np.eye(s.n)])
    f = s.force(q[None], qd[None], np.zeros(1), 1.0, s.parameters)[0]
    np.testing.assert_allclose(f, -gradV + _dissipation_force(qd, n_rods, 2.0, 5e-4), atol=1e-7)
    # printed eq. (78) for an interior rod (i = 3): -eps(...) - k(phi2 - 2 phi3 + phi4): the opposite elastic sign
    phi = q[4::3]
    printed = -0.05 * (phi[0] - 2 * phi[1] + phi[2])
    ours = f[4 + 3] - _dissipation_force(qd, n_rods, 2.0, 5e-4)[4 + 3]
    np.testing.assert_allclose(ours, -printed, atol=1e-8)


def test_rod_and_inverted_pendulum_follow_eqs_61_to_64():
    s = ex.rod_pendulum()
    q = np.array([0.1, -0.4, -1.2])
    phi = s.constraint(q[None], np.zeros(1), 2.0, s.parameters)[0]
    np.testing.assert_allclose(phi, q[:2] + np.array([-0.5 * np.cos(q[2]), -0.5 * np.sin(q[2])]), atol=1e-15)
    f = s.force(q[None], np.array([[0.0, 0.0, 2.0]]), np.array([0.3]), 2.0, s.parameters)[0]
    np.testing.assert_allclose(f, [0.0, -9.81, -0.04 * 2.0 + 0.15 * np.cos(0.6)], atol=1e-14)
    v = ex.inverted_pendulum()
    t = np.array([0.2])
    phi = v.constraint(q[None], t, 3.0, v.parameters)[0]
    want = q[:2] + np.array([-0.5 * np.cos(q[2]), -0.5 * np.sin(q[2])]) + np.array([0.0, 0.05 * np.sin(0.6)])
    np.testing.assert_allclose(phi, want, atol=1e-15)
    f = v.force(q[None], np.array([[0.0, 0.0, 1.0]]), t, 3.0, v.parameters)[0]
    np.testing.assert_allclose(f[2], -0.05 + 20.0 * (np.pi / 2 - q[2]) ** 3, atol=1e-13)
    # q0 is the tilted static equilibrium: zero generalized force after eliminating lambda
    Pq = v.constraint_jacobian(v.q0[None], np.zeros(1), 1.0, dict(p=0.0))[0]
    f0 = v.force(v.q0[None], np.zeros((1, 3)), np.zeros(1), 1.0, v.parameters)[0]
    lam = np.linalg.lstsq(Pq.T, f0, rcond=None)[0]
    assert np.abs(Pq.T @ lam - f0).max() < 1e-12
