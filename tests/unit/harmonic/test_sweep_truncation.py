"""The sweep's HB truncation indicator (SweepTruncation: products on sample angles, per-speed
band from a bound) against the harmonic convolution of balance_truncation with the
coefficients evaluated at each speed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from periodyn.examples import pendulum
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
from periodyn.harmonic.truncation import (FLOOR, BALANCE_TRUNCATION_TOL, SweepTruncation, balance_truncation,
                                          coefficient_tops)
from periodyn.model.linearization import omega_split
from periodyn.speeds import SpeedSolver
from periodyn.system import OmegaSplitModel


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


def test_the_modal_bound_holds_for_every_unbalanced_harmonic():
    """The bound that lets a harmonic go unsolved is above its exact estimate |D_l^-1 R_l|
    (8 elements: measured 1.0-1.3x), so the indicator is the largest over all harmonics."""
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=8))
    model = omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=8), 64)
    w = np.linspace(150.0, 300.0, 7)
    q = SpeedSolver(model, 12, stability=False)._balance(w)[0]
    T = SweepTruncation(model._power_spectra[:4], 12)
    top = T.tops(w)
    R = T.unbalanced(q, w)
    bound = T.bounds(R, w, top)
    Ms, Cs, Ks, _, _ = model._power_spectra
    K = (Ms.shape[0] - 1) // 2
    checked, largest = 0, np.zeros(w.size)
    for s, ws in enumerate(w):
        for i, l in enumerate(T.l[T.l <= top[s]]):
            lw = l * ws
            D = (-lw ** 2 * Ms[K] + 1j * lw * sum(ws ** p * Cs[K, ..., p] for p in range(Cs.shape[-1]))
                 + sum(ws ** p * Ks[K, ..., p] for p in range(Ks.shape[-1])))
            est = np.abs(np.linalg.solve(D, R[s, i])).max()
            largest[s] = max(largest[s], est)
            assert np.isfinite(bound[s, i]) and est <= bound[s, i]
            checked += 1
    assert checked > 100
    # the harmonics solved, by the modal iteration: measured 9e-16 from the LU
    np.testing.assert_allclose(T(q, w), largest / np.abs(q).reshape(w.size, -1).max(axis=1), rtol=1e-13)


@pytest.mark.parametrize("elements", [8, 128])
def test_the_modal_iteration_is_the_dense_solve(elements):
    """The Jacobi iteration in the mean modes gives |D_l^-1 R_l| of the LU solve (measured
    to 7e-16 (8 elements) and 4.5e-15 (128) of the largest entry, every unbalanced harmonic)."""
    model = _rod(elements)
    w = np.array([150.0, 231.54, 300.0])
    q = SpeedSolver(model, 12)._balance(w)[0]
    T = SweepTruncation(model._power_spectra[:4], 12)
    R = T.unbalanced(q, w)
    s, i = np.nonzero(np.isfinite(T.bounds(R, w, T.tops(w))))
    assert s.size >= 3 * 8
    lw = T.l[i] * w[s]
    modal, dense = T.modal_estimates(R[s, i], lw, w[s]), T.dense_estimates(R[s, i], lw, w[s])
    assert np.isfinite(modal).all()
    np.testing.assert_allclose(modal, dense, rtol=0, atol=1e-13 * dense.max())
    for part in (slice(0, 1), slice(3, 20), slice(5, None)):  # a vector's estimate is its own, to the bit
        assert np.array_equal(T.modal_estimates(R[s, i][part], lw[part], w[s][part]), modal[part])



def _rod(elements):
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=elements))
    return omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=elements), 64)


def _every_harmonic(model, q, w):
    """The indicator by the harmonic convolution with every coefficient harmonic of the
    samples and every unbalanced harmonic l = m+1 .. m+K (no cut)."""
    Ms, Cs, Ks, fs, _ = model._power_spectra
    K, Kf, m = (Ms.shape[0] - 1) // 2, (fs.shape[0] - 1) // 2, (q.shape[1] - 1) // 2
    out = np.zeros(w.size)
    for s, ws in enumerate(w):
        C = sum(ws ** p * Cs[..., p] for p in range(Cs.shape[-1]))
        Kw = sum(ws ** p * Ks[..., p] for p in range(Ks.shape[-1]))
        f = sum(ws ** p * fs[..., p] for p in range(fs.shape[-1]))
        for l in range(m + 1, m + K + 1):
            R = f[Kf + l].copy() if l <= Kf else np.zeros(model.n, complex)
            for j in range(max(-m, l - K), m + 1):
                R -= (-(j * ws) ** 2 * Ms[K + l - j] + 1j * j * ws * C[K + l - j] + Kw[K + l - j]) @ q[s, m + j]
            D = -(l * ws) ** 2 * Ms[K] + 1j * l * ws * C[K] + Kw[K]
            out[s] = max(out[s], np.abs(np.linalg.solve(D, R)).max())
    return out / np.abs(q).reshape(w.size, -1).max(axis=1)


def test_the_noise_floor_keeps_every_harmonic_that_matters():
    """32 elements: the band and the terms cut at the coefficients' noise floor give the
    indicator of every coefficient and every unbalanced harmonic (measured 1e-9 to 1.1e-8,
    the noise of the terms left out; the cut at 1e-13 of the largest: 1e-11 to 6e-11)."""
    model = _rod(32)
    w = np.array([150.0, 231.54, 300.0])
    q = SpeedSolver(model, 12, stability=False)._balance(w)[0]
    T = SweepTruncation(model._power_spectra[:4], 12)
    np.testing.assert_allclose(T(q, w), _every_harmonic(model, q, w), rtol=1e-6)


@pytest.mark.parametrize("elements", [32, 128])
def test_the_band_is_the_stiffness_harmonics_not_the_noise(elements):
    """The band ends where the omega^2 stiffness's harmonics (the same on 8 and 128 elements)
    reach the noise of the mean stiffness and damping (3e-13 of their largest at 128
    elements, from the kinematic Newton tolerance; 1e-14 at 8): 128 elements get the band of
    8 elements (measured 20-22) or a few harmonics less (16-18, its noise is higher), and the
    products take only the mass and the omega^2 stiffness (the old cut at 1e-13 of the
    largest entry took harmonic 31, the highest the samples hold, and all six terms)."""
    w = np.array([150.0, 225.0, 300.0])
    band, used = SweepTruncation(_rod(elements)._power_spectra[:4], 12).content(w)
    coarse = SweepTruncation(_rod(8)._power_spectra[:4], 12).content(w)[0]
    assert (coarse - 6 <= band).all() and (band <= coarse).all() and coarse.max() <= 22
    assert (used == [True, False, False, False, False, True]).all()  # M, C_0, C_1, K_0, K_1, K_2


def test_constant_coefficients_leave_no_harmonic_out():
    """With constant coefficients no harmonic is unbalanced: the indicator is 0 (and no
    modal bound is formed)."""
    theta = 2 * np.pi * np.arange(8) / 8
    model = OmegaSplitModel.from_samples(np.ones((8, 1, 1)), [np.full((8, 1, 1), 0.1)], [np.ones((8, 1, 1))],
                                         [np.cos(theta)[:, None]])
    w = np.array([0.5, 0.9, 3.0])
    q = SpeedSolver(model, 2, stability=False)._balance(w)[0]
    assert np.array_equal(SweepTruncation(model._power_spectra[:4], 2)(q, w), np.zeros(3))


def test_coefficient_tops_end_at_the_noise_floor():
    """The highest harmonic above FLOOR times a term's noise floor; of a term without a floor
    (0), the highest above 1e-13 of its largest."""
    k = np.abs(np.arange(-6, 7))
    decayed = np.where(k <= 3, 10.0 ** -k, 1e-14)  # harmonics 0..3, then a flat floor
    decayed[6 + 5] = 2.9 * 1e-14  # below FLOOR times the floor: noise
    flat = np.ones(13)
    tops = coefficient_tops(np.stack([decayed, flat, np.zeros(13)]), np.array([1e-14, 0.0, 0.0]))
    assert FLOOR == 3.0 and list(tops) == [3, 6, 0]
