"""The sweep's HB truncation indicator (SweepTruncation: products on sample angles, per-speed
band from a bound) against the harmonic convolution of balance_truncation with the
coefficients evaluated at each speed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from periodyn.examples import pendulum
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
from periodyn.harmonic.truncation import BALANCE_TRUNCATION_TOL, SweepTruncation, balance_truncation
from periodyn.model.linearization import omega_split
from periodyn.speeds import SpeedSolver


def _reference(model, q, w):
    Ms, Cs, Ks, fs, _ = model._power_spectra

    def at(A):
        return np.stack([sum(wi ** p * A[..., p] for p in range(A.shape[-1])) for wi in w])

    return balance_truncation(Ms, at(Cs), at(Ks), at(fs), q, w)


@pytest.mark.parametrize("case", ["rod", "pendulum"])
def test_equals_the_harmonic_convolution(case):
    if case == "rod":
        w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=4))
        model, m = omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=4), 64), 6
        w = np.linspace(150.0, 300.0, 5)
    else:
        model, m = pendulum(samples=48, length=3.11, radius=4.28, eccentricity=0.1147, zeta=0.022), 1
        w = 0.9 * math.sqrt(9.81 / 3.11) * np.array([1.0, 0.1, 0.5])
    q = SpeedSolver(model, m, stability=False)._balance(w)[0]
    ref = _reference(model, q, w)
    new = SweepTruncation(model._power_spectra[:4], m)(q, w)
    np.testing.assert_allclose(new, ref, rtol=1e-12)  # measured 4e-14 (rod), 4e-15 (pendulum)
    if case == "pendulum":
        assert new[0] > BALANCE_TRUNCATION_TOL > new[1]


def test_each_speed_is_the_same_to_the_bit_in_any_chunk():
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=4))
    model = omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=4), 64)
    w = np.linspace(150.0, 300.0, 21)  # two blocks of the sample products and part of a third
    q = SpeedSolver(model, 6, stability=False)._balance(w)[0]
    T = SweepTruncation(model._power_spectra[:4], 6)
    together = T(q, w)
    for part in (slice(0, 1), slice(3, 5), slice(2, 19), slice(15, 21), slice(20, 21)):
        assert np.array_equal(T(q[part], w[part]), together[part])
    assert np.array_equal(T(q[::-1], w[::-1]), together[::-1])
