"""Products by the nonzero entries of a sparse factor (periodyn.kernels.solvers.sparse_products)
against dense NumPy products."""

import numpy as np
import pytest

from periodyn.kernels.solvers.sparse_products import (commutator_either, commutator_entries, matmul_entries,
                                                      sparse_entries)

RNG = np.random.default_rng(5)
D = 40


def sparse(nonzero, d=D):
    S = np.zeros((d, d))
    S.ravel()[RNG.choice(d * d, nonzero, replace=False)] = RNG.standard_normal(nonzero)
    return S


def entries(S, m=D * D // 8):
    rows, cols, vals = np.empty(m, np.int64), np.empty(m, np.int64), np.empty(m)
    return rows, cols, vals, sparse_entries(S, rows, cols, vals)


def test_entries_are_listed_in_row_major_order_or_refused_beyond_the_buffer():
    S = sparse(50)
    rows, cols, vals, count = entries(S)
    i, k = np.nonzero(S)
    assert count == 50 and np.array_equal(rows[:count], i) and np.array_equal(cols[:count], k)
    assert np.array_equal(vals[:count], S[i, k])
    assert entries(S, m=49)[3] == -1 and entries(np.zeros((D, D)))[3] == 0


@pytest.mark.parametrize("nonzero", [0, 1, 120, 200])
def test_commutator_and_product_by_entries_match_dense(nonzero):
    X, S = RNG.standard_normal((D, D)), sparse(nonzero)
    rows, cols, vals, count = entries(S)
    out = np.empty((D, D))
    commutator_entries(X, rows, cols, vals, count, out)
    np.testing.assert_allclose(out, X @ S - S @ X, rtol=0, atol=1e-13 * max(1.0, np.abs(X).max()))
    matmul_entries(rows, cols, vals, count, 0.25, X, out)
    np.testing.assert_allclose(out, 0.25 * S @ X, rtol=0, atol=1e-14 * max(1.0, np.abs(X).max()))


@pytest.mark.parametrize("sparse_side", ["right", "left"])
def test_commutator_either_takes_the_sparse_factor(sparse_side):
    dense, S = RNG.standard_normal((D, D)), sparse(150)
    X, Y = (dense, S) if sparse_side == "right" else (S, dense)
    out = np.empty((D, D))
    assert commutator_either(X, Y, out, 16)
    np.testing.assert_allclose(out, X @ Y - Y @ X, rtol=0, atol=1e-13 * np.abs(dense).max())


def test_commutator_either_declines_dense_or_small_factors():
    out = np.full((D, D), 7.0)
    assert not commutator_either(RNG.standard_normal((D, D)), RNG.standard_normal((D, D)), out, 16)
    assert not commutator_either(sparse(10), sparse(10), out, D + 1)
    assert (out == 7.0).all()
