"""StackedSpectra: one real product equals the two-sided Fourier sums of every spectrum."""

import numpy as np

from periodyn.numerics.spectra import StackedSpectra, fourier_coefficients, real_basis, synthesize


def _spectrum(rng, K, shape):
    samples = rng.standard_normal((4 * K + 3,) + shape)
    return fourier_coefficients(samples, K)


def test_stacked_equals_each_synthesis():
    rng = np.random.default_rng(3)
    spectra = (_spectrum(rng, 5, (3, 3)), _spectrum(rng, 2, (3,)), _spectrum(rng, 0, (2, 4)))
    theta = rng.uniform(-7.0, 7.0, 11)
    stacked = StackedSpectra(*spectra)
    assert stacked.rows.shape == (11, 9 + 3 + 8)
    for got, X in zip(stacked.at(theta), spectra):
        assert got.shape == (11,) + X.shape[1:]
        np.testing.assert_allclose(got, synthesize(X, theta), rtol=0, atol=1e-13 * np.abs(X).sum())


def test_real_basis_layout():
    theta = np.array([0.3, 1.1])
    B = real_basis(2, theta)
    np.testing.assert_array_equal(B[:, 0], 1.0)
    np.testing.assert_allclose(B[:, 1:], np.stack([np.cos(theta), np.sin(theta), np.cos(2 * theta), np.sin(2 * theta)], 1))
