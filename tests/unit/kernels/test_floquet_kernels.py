"""Floquet kernels (periodyn.kernels.solvers.floquet) against plain-NumPy/SciPy twins."""

import numpy as np
import pytest
import scipy.linalg as sla

import periodyn
from periodyn.examples.chain import parametric_chain
from periodyn.harmonic import HarmonicOperator
from periodyn.stability.hill import _dense_eigs, select_representatives
from periodyn.kernels.solvers.floquet import _commutator_sparse, _expm, magnus6_product, magnus_monodromies, magnus_product
from periodyn.stability.magnus import gauss_angles, magnus_terms, magnus_transition

RNG = np.random.default_rng(11)


# ----------------------------------------------------------------------------- twins
def select_twin(lam, X, omega, m, n, count):
    """Cluster representatives as in select_clusters, with lstsq for the span test."""
    energy = (np.abs(X) ** 2).reshape(2 * m + 1, n, -1).sum(axis=1)
    total = energy.sum(axis=0)
    c = (np.arange(-m, m + 1) @ energy) / total
    chosen, raw, vecs = [], [], []
    for i in np.argsort(np.abs(c), kind="mergesort"):
        x = X[:, i].reshape(2 * m + 1, n) / np.linalg.norm(X[:, i])
        same = []
        for lj, vj in zip(raw, vecs):
            d = lam[i] - lj
            j = int(np.rint(d.imag / omega))
            if abs(d - 1j * omega * j) <= (1e-7 if j else 1e-10) * (abs(lj) + omega):
                shifted = np.zeros_like(vj)  # shifted[l] = vj[l + j]
                lo, hi = max(0, -j), min(2 * m + 1, 2 * m + 1 - j)
                if lo < hi:
                    shifted[lo:hi] = vj[lo + j: hi + j]
                same.append(shifted.reshape(-1))
        if same:
            U = np.stack(same, axis=1)
            coef, *_ = np.linalg.lstsq(U, x.reshape(-1), rcond=None)
            if np.linalg.norm(x.reshape(-1) - U @ coef) < 0.5:
                continue
        chosen.append(lam[i] + 1j * omega * np.rint(c[i]))
        raw.append(lam[i])
        vecs.append(x)
        if len(chosen) == count:
            break
    return np.array(chosen)


def magnus_twin(A, h):
    """Magnus transition with scipy's expm per step."""
    phi = np.eye(A.shape[1])
    for A1, A2 in zip(A[0::2], A[1::2]):
        phi = sla.expm(0.5 * h * (A1 + A2) + np.sqrt(3) / 12 * h * h * (A2 @ A1 - A1 @ A2)) @ phi
    return phi


def magnus6_twin(A, h):
    """6th-order Magnus transition (three Gauss points a step) with scipy's expm per step."""
    phi = np.eye(A.shape[1])

    def comm(X, Y):
        return X @ Y - Y @ X

    for A1, A2, A3 in zip(A[0::3], A[1::3], A[2::3]):
        a1, a2, a3 = h * A2, np.sqrt(15) / 3 * h * (A3 - A1), 10 / 3 * h * (A3 - 2 * A2 + A1)
        C1 = comm(a1, a2)
        C2 = -comm(a1, 2 * a3 + C1) / 60
        phi = sla.expm(a1 + a3 / 12 + comm(-20 * a1 - a3 + C1, a2 + C2) / 240) @ phi
    return phi


# ----------------------------------------------------------------------------- tests
@pytest.mark.parametrize("d,norm", [(2, 0.1), (5, 0.49), (8, 3.0), (8, 40.0)])
def test_expm_matches_scipy(d, norm):
    X = RNG.standard_normal((d, d))
    X -= 0.6 * X.T  # mostly rotation, as the step generators of lightly damped systems
    X *= norm / np.abs(X).sum(axis=0).max()
    out, scratch = np.empty((d, d)), np.empty((6, d, d))
    _expm(X, out, scratch)
    ref = sla.expm(X)
    np.testing.assert_allclose(out, ref, atol=5e-14 * np.abs(ref).max() * max(1.0, norm))


@pytest.mark.parametrize("norm", [0.3, 3.0, 8.0])
def test_expm_of_a_sparse_generator_matches_scipy(norm):
    """A chain's step generator h [[0, I], [-K, -C]] (tridiagonal K: few nonzero entries,
    X^2 and X^3 from them)."""
    n = 40
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1) + np.diag(RNG.uniform(0.5, 1.5, n))
    X = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -0.05 * np.eye(n)]])
    X *= norm / np.abs(X).sum(axis=0).max()
    out, scratch = np.empty((2 * n, 2 * n)), np.empty((6, 2 * n, 2 * n))
    _expm(X, out, scratch)
    ref = sla.expm(X)
    np.testing.assert_allclose(out, ref, atol=5e-14 * np.abs(ref).max() * max(1.0, norm))


@pytest.mark.parametrize("scale", [1e80, np.inf])
def test_expm_of_an_overflowing_generator_is_nan_at_once(scale):
    """||X^4|| beyond the double range: NaN (a non-finite monodromy, reported by the caller)
    instead of halving an infinite norm for ever."""
    X = np.array([[0.0, 1.0], [-1.0, -0.1]]) * scale
    out, scratch = np.empty((2, 2)), np.empty((6, 2, 2))
    _expm(X, out, scratch)
    assert np.isnan(out).all()


def _slider_crank_terms(steps, points):
    """The slider crank's Magnus terms at ``points`` Gauss points of ``steps`` steps, the model, the angles."""
    model = periodyn.examples.slider_crank(damping=0.02, samples=64)
    theta = gauss_angles(steps, points=points)
    terms, a = magnus_terms(*(periodyn.numerics.spectra.synthesize(X, theta) for X in model._power_spectra[:3]))
    return terms, a, model, theta


@pytest.mark.parametrize("product, twin, steps, points", [(magnus_product, magnus_twin, 64, 2),
                                                          (magnus6_product, magnus6_twin, 48, 3)])
def test_magnus_products_match_twins_and_batch_matches_single(product, twin, steps, points):
    terms = _slider_crank_terms(steps, points)[0]
    omegas = np.array([150.0, 230.0])
    batch = np.empty((2, 8, 8))
    magnus_monodromies(terms, omegas, batch, points)
    for w, phi_batch in zip(omegas, batch):
        A = terms[0] + w * terms[1] + w * w * terms[2]
        h = 2 * np.pi / (w * steps)
        single = np.empty((8, 8))
        product(A, h, single)
        np.testing.assert_array_equal(single, phi_batch)
        np.testing.assert_allclose(single, twin(A, h), atol=1e-11 * np.abs(single).max())


@pytest.mark.parametrize("nonzero", [0, 1, 40, 800, 6400])
def test_commutator_by_nonzero_entries_matches_the_products(nonzero):
    """X S - S X for S with few nonzero entries (by its entries) and many (by two products)."""
    d = 80
    X, S = RNG.standard_normal((d, d)), np.zeros((d, d))
    S.ravel()[RNG.choice(d * d, nonzero, replace=False)] = RNG.standard_normal(nonzero)
    out, tmp = np.empty((d, d)), np.empty((d, d))
    _commutator_sparse(X, S, out, tmp)
    np.testing.assert_allclose(out, X @ S - S @ X, rtol=0, atol=1e-13 * max(1.0, np.abs(X @ S).max()))


def test_magnus6_of_a_generator_varying_in_few_entries_matches_twin():
    """An 80 x 80 chain-like generator [[0, I], [-K(t), -C]] whose stiffness varies on its
    diagonal only (the step differences then take the commutator's entry path)."""
    n, steps = 40, 6
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    theta = gauss_angles(steps, points=3)
    A = np.zeros((3 * steps, 2 * n, 2 * n))
    A[:, :n, n:] = np.eye(n)
    A[:, n:, n:] = -0.05 * np.eye(n)
    A[:, n:, :n] = -K
    A[:, np.arange(n, 2 * n), np.arange(n)] -= 0.3 * np.cos(theta)[:, None] ** 2 * np.linspace(0.5, 1.5, n)
    h = np.pi / steps
    phi = np.empty((2 * n, 2 * n))
    magnus6_product(A, h, phi)
    np.testing.assert_allclose(phi, magnus6_twin(A, h), atol=1e-11 * np.abs(phi).max())


def test_unbalanced_transition_is_similar_to_the_balanced_one():
    """magnus_transition of (q, q') against the balanced product: D^-1 Phi D with D = (a, 1)."""
    steps = 64
    terms, a, model, theta = _slider_crank_terms(steps, 2)
    for w in (150.0, 230.0):
        A = terms[0] + w * terms[1] + w * w * terms[2]
        h = 2 * np.pi / (w * steps)
        single = np.empty((8, 8))
        magnus_product(A, h, single)
        S = model.at(w).spectra
        unbalanced = magnus_transition(*(periodyn.numerics.spectra.synthesize(X, theta) for X in (S.mass, S.damping,
                                                                                          S.stiffness)), h)
        np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(unbalanced)),
                                   np.sort_complex(np.linalg.eigvals(single)), atol=1e-10)
        D = np.r_[np.full(4, a), np.ones(4)]
        np.testing.assert_allclose(unbalanced, single * D[None, :] / D[:, None], atol=1e-9 * np.abs(unbalanced).max())


@pytest.mark.parametrize("builder,m,speeds", [
    (lambda: periodyn.examples.pendulum(samples=36), 8, (0.7, 2.3, 4.2, 4.4)),  # 4.2, 4.4: period doubling
    (lambda: parametric_chain(3, samples=64), 10, (11.0, 40.0, 97.0)),
])
def test_cluster_selection_matches_twin(builder, m, speeds):
    model = builder()
    for w in speeds:
        system = model.at(w)
        op = HarmonicOperator.for_system(system, m).at(w)
        lam, X = _dense_eigs(op)
        ref = select_twin(lam, X, w, m, system.n, 2 * system.n)
        got = select_representatives(lam, X, w, m, system.n, 2 * system.n)[0]
        assert got.size == ref.size == 2 * system.n
        # equal up to the member of a period-doubling pair (centroids +-1/2, a tie) taken
        np.testing.assert_allclose(np.sort(got.real), np.sort(ref.real), atol=1e-12 * (1 + np.abs(ref).max()))
        T = 2 * np.pi / w
        np.testing.assert_allclose(np.sort_complex(np.exp(got * T)), np.sort_complex(np.exp(ref * T)), atol=1e-10)
