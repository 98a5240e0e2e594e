"""The certified Magnus flow of sampled orbits (periodyn.stability.orbit_flow) against the
monodromy matrix by adaptive integration (scipy DOP853), and its use by IHB's "auto"."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import periodyn
from periodyn.nonlinear.ihb_solver import IHBProblem, ihb
from periodyn.stability.methods import flow_choice
from periodyn.kernels.solvers.sampled_flow import gauss_values, sampled_monodromy
from periodyn.stability.orbit_flow import SampledGenerator, flow_exponents


def mathieu(a, b, c, k):
    """A(t) of y'' + c y' + (a + b cos(k t)) y = 0 (first order, y = (x, x'))."""
    return lambda t: np.array([[0.0, 1.0], [-(a + b * np.cos(k * t)), -c]])


def reference_multipliers(A, period):
    """Eigenvalues of the monodromy matrix by DOP853 (rtol 1e-12)."""
    d = A(0.0).shape[0]
    sol = solve_ivp(lambda t, y: (A(t) @ y.reshape(d, d)).ravel(), (0.0, period), np.eye(d).ravel(),
                    method="DOP853", rtol=1e-12, atol=1e-14)
    return np.linalg.eigvals(sol.y[:, -1].reshape(d, d))


def samples(A, period, p):
    return np.array([A(period * j / p) for j in range(p)])


@pytest.mark.parametrize("a, b, k", [(1.0, 0.3, 1), (0.3, 0.2, 2), (1.0, 0.4, 2), (2.0, 0.5, 1)])
def test_moduli_match_monodromy(a, b, k):
    """Stable and unstable (inside the first tongue: a = 1 with k = 2) Mathieu cases."""
    omega = 1.0
    A = mathieu(a, b, 0.04, k)
    period = 2 * np.pi / omega
    fl = flow_exponents(samples(A, period, 32), omega)
    ref = np.sort(np.abs(reference_multipliers(A, period)))
    assert fl is not None and fl.method == "magnus"
    assert np.allclose(np.sort(np.abs(fl.multipliers)), ref, rtol=1e-7, atol=0)
    assert np.log(ref[-1]) == pytest.approx(np.log(fl.max_multiplier), abs=1e-7)
    assert fl.stable == (np.log(ref[-1]) <= 1e-6)


def test_unstable_case_is_flagged():
    A = mathieu(1.0, 0.4, 0.04, 2)
    fl = flow_exponents(samples(A, 2 * np.pi, 32), 1.0)
    assert not fl.stable and fl.max_multiplier > 1.05


def test_half_period_detected_and_same_result():
    """cos(2t) repeats after half a period, cos(t) does not; the half-period route (Phi(T/2)^2)
    agrees with the reference."""
    S2, S1 = samples(mathieu(0.6, 0.3, 0.02, 2), 2 * np.pi, 32), samples(mathieu(0.6, 0.3, 0.02, 1), 2 * np.pi, 32)
    assert "half period" in flow_exponents(S2, 1.0).reason and "half period" not in flow_exponents(S1, 1.0).reason
    ref = np.sort(np.abs(reference_multipliers(mathieu(0.6, 0.3, 0.02, 2), 2 * np.pi)))
    assert np.allclose(np.sort(np.abs(flow_exponents(S2, 1.0).multipliers)), ref, rtol=1e-7)


def interpolation_matrix(p, steps):
    """(3 steps, p) weights of the trigonometric interpolant (harmonics 0..(p-1)//2) of p samples
    at the Gauss angles of ``steps`` equal steps (the kernel's interpolation, written as weights)."""
    theta = (np.arange(steps)[:, None] + np.array([0.5 - np.sqrt(15) / 10, 0.5, 0.5 + np.sqrt(15) / 10])).ravel()
    diff = theta[:, None] * 2 * np.pi / steps - 2 * np.pi * np.arange(p)[None, :] / p
    k = np.arange(1, (p - 1) // 2 + 1)
    return (1.0 + 2.0 * np.cos(diff[:, :, None] * k).sum(axis=2)) / p


@pytest.mark.parametrize("p", [15, 16])
def test_interpolation_is_exact_for_resolved_harmonics(p):
    steps = 8
    x = np.cos(3 * 2 * np.pi * np.arange(p) / p) + 0.5 * np.sin(7 * 2 * np.pi * np.arange(p) / p)
    theta = (np.arange(steps)[:, None] + np.array([0.5 - np.sqrt(15) / 10, 0.5, 0.5 + np.sqrt(15) / 10])).ravel()
    theta *= 2 * np.pi / steps
    got = gauss_values(np.stack([x, 2 * x], axis=1), steps)
    assert np.allclose(got[:, 0], np.cos(3 * theta) + 0.5 * np.sin(7 * theta), atol=1e-13)
    assert np.allclose(got[:, 1], 2 * interpolation_matrix(p, steps) @ x, atol=1e-13)


def test_stiff_orbit_goes_to_the_ladder():
    A = samples(mathieu(1e6, 0.3, 0.04, 1), 2 * np.pi, 16)
    assert not flow_choice(SampledGenerator.from_samples(A).stiffness(1.0))[0]
    assert flow_choice(SampledGenerator.from_samples(samples(mathieu(1.0, 0.3, 0.04, 1), 2 * np.pi, 16)).stiffness(1.0))[0]


def sparse_samples(p=12, d=6, seed=3):
    """Samples (p, d, d) of which a few entries vary, the others constant and nonzero."""
    rng = np.random.default_rng(seed)
    A = np.repeat(rng.normal(size=(1, d, d)), p, axis=0)
    for i, j in [(3, 0), (4, 1), (5, 5), (0, 4)]:
        A[:, i, j] += rng.normal(size=p) * 10.0
    return A


def test_sampled_generator_keeps_only_the_varying_entries():
    A = sparse_samples()
    gen = SampledGenerator.from_samples(A)
    assert gen.varying.size == 4 and np.array_equal(gen.samples, A)
    T = 2 * np.pi / 1.7 * 2
    assert gen.stiffness(1.7, 2) == pytest.approx(np.abs(A).sum(axis=1).max() * T, rel=1e-14)


@pytest.mark.parametrize("damping", ["constant", "varying"])
def test_generator_from_blocks_equals_the_one_from_full_samples(damping):
    """[[0, I], [K_j, C_j]] from its blocks (a broadcast block taken as constant) equals the
    generator of the full samples, entry lists included."""
    rng = np.random.default_rng(4)
    p, n = 10, 5
    K = np.repeat(rng.normal(size=(1, n, n)), p, axis=0)
    K[:, [0, 3, 3], [1, 0, 4]] += rng.normal(size=(p, 3))
    C = np.broadcast_to(rng.normal(size=(n, n)), (p, n, n))
    if damping == "varying":
        C = C.copy()
        C[:, 2, 2] += rng.normal(size=p)
    full = np.zeros((p, 2 * n, 2 * n))
    full[:, :n, n:] = np.eye(n)
    full[:, n:, :n], full[:, n:, n:] = K, C
    got, ref = SampledGenerator.from_blocks(K, C), SampledGenerator.from_samples(full)
    assert np.array_equal(got.varying, ref.varying) and got.varying.size == (4 if damping == "varying" else 3)
    assert np.array_equal(got.values, ref.values) and np.array_equal(got.constant, ref.constant)


@pytest.mark.parametrize("constant_entry", [False, True])
def test_sparse_monodromy_matches_the_full_samples(constant_entry):
    """The monodromy from the varying entries equals Magnus on the full interpolated samples;
    an entry given among the varying ones but constant keeps its value exactly."""
    from periodyn.kernels.solvers.floquet import magnus6_product
    A = 0.1 * sparse_samples()
    gen = SampledGenerator.from_samples(A)
    steps, p, d = 8, A.shape[0], A.shape[1]
    full = np.einsum("gp,pij->gij", interpolation_matrix(p, steps), A)
    varying, values = gen.varying, gen.values
    if constant_entry:  # entry (2, 2) listed as varying with its constant samples
        varying, values = np.append(varying, 2 * d + 2), np.hstack([values, np.full((p, 1), A[0, 2, 2])])
        full[:, 2, 2] = A[0, 2, 2]
    ref, phi = np.empty((d, d)), np.empty((d, d))
    magnus6_product(np.ascontiguousarray(full), 1.0 / steps, ref)
    sampled_monodromy(gen.constant, varying, values, steps, 1.0, phi)
    assert np.allclose(phi, ref, rtol=1e-13, atol=1e-13 * np.abs(ref).max())


def test_a_six_by_six_generator_matches_the_monodromy():
    """More than one degree of freedom (LAPACK multipliers): a periodically varying 3-DOF system."""
    rng = np.random.default_rng(2)
    K, C, B = np.diag([1.0, 2.3, 4.1]) + 0.1 * rng.normal(size=(3, 3)), 0.03 * np.eye(3), 0.3 * rng.normal(size=(3, 3))

    def A(t):
        return np.block([[np.zeros((3, 3)), np.eye(3)], [-(K + B * np.cos(t)), -C]])

    fl = flow_exponents(samples(A, 2 * np.pi, 24), 1.0)
    ref = np.sort(np.abs(reference_multipliers(A, 2 * np.pi)))
    assert fl is not None and np.allclose(np.sort(np.abs(fl.multipliers)), ref, rtol=1e-7)


def test_an_eighty_by_eighty_chain_generator_matches_the_monodromy():
    """A 40-mass chain whose grounding stiffness varies with cos^2 t (half-period samples;
    sparse step generators, multipliers by the double-shift QR)."""
    n = 40
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    profile = np.linspace(0.2, 0.6, n)

    def A(t):
        return np.block([[np.zeros((n, n)), np.eye(n)], [-(K + np.diag(0.5 + profile * np.cos(t) ** 2)),
                                                         -0.05 * np.eye(n)]])

    fl = flow_exponents(samples(A, 2 * np.pi, 32), 1.0)
    ref = np.sort(np.abs(reference_multipliers(A, 2 * np.pi)))
    assert fl is not None and "half period" in fl.reason
    assert np.allclose(np.sort(np.abs(fl.multipliers)), ref, rtol=1e-7)


def duffing():
    def force(q, qd, t, w):
        return -0.05 * qd - q - 0.1 * q ** 3 + 0.18 * np.cos(w * t)[:, None]

    def jac(q, qd, t, w):
        return (-1.0 - 0.3 * q ** 2)[:, :, None], np.full((len(t), 1, 1), -0.05)

    return periodyn.DAE(np.eye(1), force, force_jacobian=jac, vectorized=True)


@pytest.mark.parametrize("omega", [0.8, 1.2, 1.5])
def test_ihb_auto_takes_the_flow_and_matches_the_linearized_monodromy(omega):
    """Duffing orbits (H = 7): "auto" is the flow of the samples; its multiplier moduli agree
    with DOP853 on the linearized orbit."""
    s = duffing()
    prob = IHBProblem(s, 7)
    X = prob.newton(prob.from_solution(ihb(s, omega, 7, stability=None)), omega).x
    fl, ref = prob.exponents(X, omega, None, "auto"), prob.exponents(X, omega, None, "monodromy")
    assert "Magnus flow of the orbit's samples" in fl.reason
    assert np.allclose(np.sort(np.abs(fl.multipliers)), np.sort(np.abs(ref.multipliers)), rtol=1e-8)
    assert fl.omega == omega and fl.stable == ref.stable


@pytest.mark.parametrize("phi", [[[0.9, 0.3], [-0.4, 0.8]], [[2.0, 1.0], [1.0, 3.0]], [[1e8, 1.0], [0.0, 1e-8]],
                                 [[0.0, 0.0], [0.0, 0.0]], [[-1.0, 0.5], [0.0, -1.0]]])
def test_two_by_two_eigenvalues_match_lapack(phi):
    from periodyn.kernels.solvers.sampled_flow import _multipliers
    phi = np.array(phi)
    got, ref = np.sort_complex(_multipliers(phi)), np.sort_complex(np.linalg.eigvals(phi))
    assert np.allclose(got, ref, rtol=1e-12, atol=1e-300)
