"""The one Hill/HB operator (periodyn.harmonic): blocks against a direct assembly from
NumPy-FFT spectra, polynomial evaluation at many speeds, the HB storage choice, and the
input/result checks."""

import numpy as np
import pytest

import periodyn
from periodyn.errors import ConvergenceError, InputError
from periodyn.examples.chain import parametric_chain
from periodyn.harmonic import HarmonicOperator, HillOperator, block_pattern, first_order_matrix, real_form
from periodyn.harmonic.balance import BalanceStorage, balance_storage, solve_balance


def direct_blocks(system, m):
    """HB matrix W, Hill V and Mh ((2m+1)n square, eq. 18 and 26-27) by loops over the
    harmonic pairs, from spectra of the samples by numpy.fft, and the force vector."""
    p, n = system.samples, system.n
    spec = [np.fft.fft(a, axis=0) / p for a in (system.mass, system.damping, system.stiffness, system.force)]
    K = (p - 1) // 2

    def coef(X, d):
        return X[d % p] if abs(d) <= K else np.zeros_like(X[0])

    N, w = (2 * m + 1) * n, system.omega
    W, V, Mh = (np.zeros((N, N), complex) for _ in range(3))
    for k in range(-m, m + 1):
        for l in range(-m, m + 1):
            Md, Cd, Kd = (coef(X, k - l) for X in spec[:3])
            rows, cols = slice((k + m) * n, (k + m + 1) * n), slice((l + m) * n, (l + m + 1) * n)
            W[rows, cols] = Kd + 1j * l * w * Cd - (l * w) ** 2 * Md
            V[rows, cols] = Cd + 2j * l * w * Md
            Mh[rows, cols] = Md
    f = np.concatenate([coef(spec[3], k) for k in range(-m, m + 1)])
    return W, V, Mh, f


@pytest.mark.parametrize("builder,m,w", [
    (lambda: parametric_chain(3, samples=64), 10, 37.0),
    (lambda: periodyn.examples.pendulum(samples=36), 8, 2.9),
    (lambda: periodyn.examples.slider_crank(damping=0.02, samples=64), 6, 210.0),
])
def test_operator_blocks_equal_direct_assembly(builder, m, w):
    """From the omega-polynomial model terms and from the single system at omega alike."""
    model = builder()
    system = model.at(w)
    W, V, Mh, f = direct_blocks(system, m)
    for op in (HarmonicOperator.for_model(model, m).at(w), HarmonicOperator.for_system(system, m).at(w)):
        scale = np.abs(W).max()
        np.testing.assert_allclose(op.dense(0), W, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(op.W.toarray(), W, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(op.dense(1), V, rtol=0, atol=1e-12 * np.abs(V).max())
        np.testing.assert_allclose(op.dense(2), Mh, rtol=0, atol=1e-13 * np.abs(Mh).max())
        np.testing.assert_allclose(op.rhs, f, rtol=0, atol=1e-13 * np.abs(f).max())


def test_polynomial_terms_at_many_speeds():
    """at_many, banded_many, real_balance_many and real_first_order_many equal .at(w) and
    the real form of the first-order matrix built from its blocks."""
    model, m = parametric_chain(2, samples=32), 5
    op = HarmonicOperator.for_model(model, m)
    speeds = np.array([5.0, 40.0, 90.0])
    W, V, rhs = op.at_many(speeds)
    ab, b = op.banded_many(speeds)
    A, br = op.real_balance_many(speeds)
    R = op.real_first_order_many(speeds)
    pat = op.pattern
    for i, w in enumerate(speeds):
        one = op.at(w)
        np.testing.assert_allclose(W[i], one.blocks[0], rtol=1e-14, atol=1e-9)
        np.testing.assert_allclose(V[i], one.blocks[1], rtol=1e-14, atol=1e-12)
        np.testing.assert_allclose(rhs[i], one.rhs, rtol=1e-14)
        np.testing.assert_allclose(ab[i], pat.banded(one.blocks[0]), rtol=1e-14, atol=1e-9)
        np.testing.assert_allclose(b[i], one.rhs, rtol=1e-14)
        np.testing.assert_allclose(A[i], real_form(one.dense(0), m, 2, halves=1), rtol=1e-13, atol=1e-9)
        direct = real_form(first_order_matrix(one.dense(0), one.dense(1),
                                              __import__("scipy.linalg").linalg.lu_factor(one.dense(2))), m, 2)
        np.testing.assert_allclose(R[i], direct, rtol=1e-12, atol=1e-9 * np.abs(direct).max())
        np.testing.assert_allclose(op.at(w, real_first_order=True).real_first_order_matrix(), R[i], rtol=1e-13,
                                   atol=1e-14 * np.abs(R[i]).max())  # Horner vs einsum: round-off


def test_balance_storage_by_cost_and_all_storages_agree():
    """A narrow band is stored banded, a band coupling all harmonics dense (before: sparse
    LU of an effectively dense matrix); the three factorizations give the same harmonics."""
    assert balance_storage(block_pattern(20, 8, 2)).kind == "banded"
    wide = balance_storage(block_pattern(64, 1, 128))
    assert wide.kind == "dense" and "N = 129" in wide.reason
    system = periodyn.examples.slider_crank(damping=0.02, samples=64).at(230.0)
    op = HarmonicOperator.for_system(system, 12).at(230.0)
    assert balance_storage(op.pattern).kind == "dense"
    solutions = [solve_balance(op, BalanceStorage(kind, "test")) for kind in ("dense", "banded", "sparse")]
    for q, residual in solutions:
        assert residual < 1e-12
        np.testing.assert_allclose(q, solutions[0][0], rtol=0, atol=1e-10 * np.abs(solutions[0][0]).max())


@pytest.mark.parametrize("bad", [0, -1, 2.0, True, "8"])
def test_harmonics_must_be_a_positive_integer(pendulum_model, bad):
    """m = 0 used to return amplitude 0 and 'stable' inside the pendulum's unstable band."""
    system = pendulum_model.at(0.95 * pendulum_model.metadata["omega0"])
    for call in (lambda: periodyn.periodic_solution(system, bad),
                 lambda: periodyn.characteristic_exponents(system, bad, "dense"),
                 lambda: periodyn.solve_point(system, bad)):
        with pytest.raises(InputError, match=r"harmonics must be an integer m >= 1.*harmonics=8"):
            call()
    assert not periodyn.characteristic_exponents(system, 8, "dense").stable  # inside [0.9187, 1.0233] w0


def test_non_finite_spectra_are_refused():
    n, K = 2, 3
    mass = np.zeros((2 * K + 1, n, n), complex)
    mass[K] = np.eye(n)
    stiffness = 0.1 * mass.copy()
    stiffness[K + 1, 0, 1] = np.nan
    with pytest.raises(InputError, match="stiffness spectrum has NaN or inf"):
        periodyn.hill_exponents(mass, 0.01 * mass, stiffness, 1.0, 2)


@pytest.mark.filterwarnings("ignore:overflow", "ignore:invalid value")
def test_non_finite_balance_solution_raises():
    """Entries near the float range overflow in the elimination: reported, not returned
    (NaN, or a wrong solution with relative residual 1.6 from the banded and sparse LU)."""
    pat = block_pattern(1, 1, 2)
    W = np.where(pat.k_index == pat.l_index, 1.0, -1.0)[:, None, None] * 1.5e308 + 0j
    op = HillOperator(1.0, pat, (W, W, W), np.ones(3, complex), False)
    for kind in ("dense", "banded", "sparse"):
        with pytest.raises(ConvergenceError, match="non-finite or inaccurate solution"):
            solve_balance(op, BalanceStorage(kind, "test"))


def test_non_finite_monodromy_raises():
    from periodyn.stability.monodromy import exponents_from_monodromy

    Phi = np.eye(2)
    Phi[0, 1] = np.inf
    with pytest.raises(ConvergenceError, match="monodromy matrix .* is not finite"):
        exponents_from_monodromy(Phi, 1.0, "magnus")


def test_tail_from_magnitudes_equals_spectral_tail():
    from periodyn.harmonic.operator import _harmonic_magnitudes, _tail
    from periodyn.numerics.spectra import spectral_tail

    rng = np.random.default_rng(3)
    for K in (0, 1, 4, 9):
        X = rng.standard_normal((2 * K + 1, 3, 2)) * np.exp(-np.abs(np.arange(-K, K + 1)))[:, None, None]
        assert _tail(_harmonic_magnitudes(X)) == spectral_tail(X)
    assert _tail(_harmonic_magnitudes(np.zeros((5, 2, 2)))) == spectral_tail(np.zeros((5, 2, 2))) == 0.0
