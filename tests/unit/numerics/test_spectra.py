import numpy as np
import pytest

from periodyn.numerics.spectra import fourier_coefficients, sample_angles, spectral_tail, synthesize, to_samples


def test_coefficients_of_a_trigonometric_polynomial():
    th = sample_angles(9)
    x = 1 + 2 * np.cos(th) + 3 * np.sin(2 * th)
    c = fourier_coefficients(x)
    expected = np.zeros(9, complex)
    expected[4], expected[5], expected[3] = 1, 1, 1
    expected[6], expected[2] = -1.5j, 1.5j
    np.testing.assert_allclose(c, expected, atol=1e-15)


def test_matches_plain_numpy_fft_for_stacked_matrices():
    rng = np.random.default_rng(0)
    x = rng.standard_normal((16, 3, 3))
    c = fourier_coefficients(x)
    ref = np.fft.fft(x, axis=0) / 16
    np.testing.assert_allclose(c[7:], ref[:8], atol=1e-15)
    np.testing.assert_allclose(c[:7], ref[9:], atol=1e-15)


def test_broadcast_and_strided_inputs_do_not_corrupt_cached_plans():
    """Regression: a zero-stride (broadcast) input once poisoned the cached FFTW plan."""
    rng = np.random.default_rng(1)
    a = rng.standard_normal((32, 1))
    before = fourier_coefficients(a)
    fourier_coefficients(np.broadcast_to(np.eye(1), (32, 1, 1)))
    fourier_coefficients(rng.standard_normal((64, 2))[::2, :1])
    np.testing.assert_array_equal(fourier_coefficients(a), before)


@pytest.mark.parametrize("p", [15, 16, 40])
def test_round_trip_and_synthesis_agree(p):
    rng = np.random.default_rng(p)
    c = fourier_coefficients(rng.standard_normal((p, 2)))
    np.testing.assert_allclose(to_samples(c, p), synthesize(c, sample_angles(p)), atol=1e-13)
    fine = 3 * p + 1
    np.testing.assert_allclose(to_samples(c, fine), synthesize(c, sample_angles(fine)), atol=1e-13)


def test_too_many_harmonics_is_refused():
    with pytest.raises(ValueError, match="at least 21 samples"):
        fourier_coefficients(np.zeros((8, 1)), max_harmonic=10)


def test_spectral_tail_is_small_for_resolved_series():
    th = sample_angles(64)
    assert spectral_tail(fourier_coefficients(np.cos(th))) < 1e-14
    assert spectral_tail(fourier_coefficients(np.abs(np.sin(th)))) > 1e-4
