"""The constraint-Jacobian LU kernel (kernels/lu.py) against LAPACK (numpy.linalg.solve),
on dense, sparse and permuted matrices and on an element model's constraint Jacobian."""

import numpy as np
import pytest

from periodyn.examples.slider_crank_rod import slider_crank_model
from periodyn.kernels.mechanism.constraint_system import allocate_equations, equations
from periodyn.kernels.mechanism.lu import factor, lu_factor, lu_solve, lu_solve_transposed
from periodyn.model.kinematics import nominal_configurations


def _sparse(n, rng, density=0.15):
    A = np.where(rng.random((n, n)) < density, rng.standard_normal((n, n)), 0.0)
    A[np.arange(n), rng.permutation(n)] += 3.0  # regular, with pivots off the diagonal
    return A


@pytest.mark.parametrize("n, dense", [(1, True), (7, True), (40, True), (60, False), (150, False)])
def test_solves_match_lapack(n, dense):
    rng = np.random.default_rng(n)
    A = rng.standard_normal((n, n)) if dense else _sparse(n, rng)
    B = rng.standard_normal((n, 5))
    LU, piv = factor(A)
    X = B.copy()
    lu_solve(LU, piv, X)
    ref = np.linalg.solve(A, B)
    scale = np.abs(ref).max()
    np.testing.assert_allclose(X, ref, rtol=0, atol=1e-12 * scale)
    xt = lu_solve_transposed(LU, piv, B[:, 0].copy())
    reft = np.linalg.solve(A.T, B[:, 0])
    np.testing.assert_allclose(xt, reft, rtol=0, atol=1e-12 * np.abs(reft).max())
    np.testing.assert_allclose(A @ X, B, rtol=0, atol=1e-11 * np.abs(A).max() * scale)


def test_factor_reconstructs_the_permuted_matrix():
    rng = np.random.default_rng(3)
    A = _sparse(30, rng)
    LU, piv = factor(A)
    L = np.tril(LU, -1) + np.eye(30)
    U = np.triu(LU)
    PA = A.copy()
    for k, p in enumerate(piv):
        PA[[k, p]] = PA[[p, k]]
    np.testing.assert_allclose(L @ U, PA, rtol=0, atol=1e-13 * np.abs(A).max())
    assert np.all(np.abs(np.tril(LU, -1)) <= 1.0 + 1e-15)  # partial pivoting bounds the multipliers


def test_singular_matrix_names_its_column():
    A = np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0], [0.0, 0.0, 1.0]])
    assert lu_factor(A.copy(), np.empty(3, dtype=np.int64)) == 2
    with pytest.raises(np.linalg.LinAlgError, match="singular constraint Jacobian"):
        factor(A)


def test_constraint_jacobian_of_a_rod_chain():
    """The transfer Jacobian F_q = J^-1 b_q of the slider-crank with 8 rod elements."""
    model = slider_crank_model(1e-4, rod_elements=8)
    arr = model.arrays
    x = nominal_configurations(model, 8)[3]
    D, Dx, Dxx, Dxxx, Phi, J = allocate_equations(arr)
    equations(arr, x, arr.rhs0, D, Dx, Dxx, Dxxx, Phi, J)
    LU, piv = factor(J)
    Fq = arr.rhs_q.copy()
    lu_solve(LU, piv, Fq)
    ref = np.linalg.solve(J, arr.rhs_q)
    np.testing.assert_allclose(Fq, ref, rtol=0, atol=1e-13 * np.abs(ref).max())


@pytest.mark.parametrize("n, dense", [(5, True), (40, True), (120, False)])
def test_condition_estimate_bounds_the_lapack_value(n, dense):
    """Hager's estimate from the factors: never above the 1-norm condition number
    (numpy.linalg.cond, from the explicit inverse, itself accurate to about cond * eps
    relative, 1e-5 for the graded matrix) and, on these matrices, within a factor 3 of it,
    including an ill-conditioned matrix (singular values down to 1e-11)."""
    from periodyn.kernels.mechanism.lu import inverse_norm1, norm1

    rng = np.random.default_rng(n + 11)
    A = rng.standard_normal((n, n)) if dense else _sparse(n, rng)
    U, _, Vt = np.linalg.svd(rng.standard_normal((n, n)))
    graded = U @ np.diag(np.logspace(0, -11, n)) @ Vt
    for B in (A, graded, np.diag(rng.uniform(0.5, 2.0, n))):
        LU, piv = factor(B)
        estimate = norm1(B) * inverse_norm1(LU, piv)
        exact = np.linalg.cond(B, 1)
        assert exact / 3 <= estimate <= exact * (1 + 1e-12 + 10 * exact * np.finfo(float).eps)


@pytest.mark.parametrize("n, dense", [(1, True), (30, True), (150, False)])
def test_transposed_solve_of_many_columns_matches_lapack(n, dense):
    from periodyn.kernels.mechanism.lu import lu_solve_transposed_many

    rng = np.random.default_rng(n + 5)
    A = rng.standard_normal((n, n)) if dense else _sparse(n, rng)
    B = rng.standard_normal((n, 9))
    LU, piv = factor(A)
    X = B.copy()
    lu_solve_transposed_many(LU, piv, X)
    ref = np.linalg.solve(A.T, B)
    np.testing.assert_allclose(X, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
