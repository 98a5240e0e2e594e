"""The Magnus ladder over half a period when the coefficients have a half-period
symmetry X(theta + pi) = P X(theta) P (the Cardan shaft: bending flips sign, torsion
does not): detection of P, and the exponents against the full-period ladder and the
DOP853 monodromy."""

import numpy as np
import pytest

import periodyn
from periodyn.stability.magnus import MagnusLadder, half_period_signs

EPS, MU, NU = 0.3, 0.2, 0.6  # cos 2 theta on the diagonal, cos theta in the coupling, speed


def _stiffness(theta, coupling):
    """Two oscillators, a 2 theta modulation on each and a coupling of harmonic 1."""
    c2, c1 = EPS * np.cos(2 * theta), coupling * np.cos(theta)
    return np.array([[1.0 + c2, c1], [c1, 2.2 - c2]])


def _spectra(coupling=MU, diagonal_odd=0.0):
    """Two-sided spectra (5, 2, 2) of M = I, C = 0.02 I, K(theta) (+ cos theta on K_11)."""
    M, C, K = np.zeros((5, 2, 2)), np.zeros((5, 2, 2, 1)), np.zeros((5, 2, 2, 1))
    M[2], C[2, :, :, 0] = np.eye(2), 0.02 * np.eye(2)
    K[2, :, :, 0] = np.diag([1.0, 2.2])
    for k in (1, 3):
        K[k, :, :, 0] = K[4 - k, :, :, 0] = 0.5 * np.array([[0.0, coupling], [coupling, 0.0]]) + \
            0.5 * np.diag([diagonal_odd, 0.0])
    for k in (0, 4):
        K[k, :, :, 0] = 0.5 * np.diag([EPS, -EPS])
    return M, C, K


def test_signs_of_the_half_period_symmetry():
    np.testing.assert_array_equal(half_period_signs(*_spectra()), [1.0, -1.0])
    np.testing.assert_array_equal(half_period_signs(*_spectra(coupling=0.0)), [1.0, 1.0])
    assert half_period_signs(*_spectra(diagonal_odd=0.1)) is None  # harmonic 1 on a diagonal entry


@pytest.mark.parametrize("speed", [0.9, 1.6, 2.9])
def test_half_period_ladder_equals_full_period_and_monodromy(speed):
    half = MagnusLadder(*_spectra())
    assert half.span == np.pi
    full = MagnusLadder(*_spectra(diagonal_odd=1e-30))  # below the detection threshold: no symmetry
    assert full.signs is not None  # a negligible entry does not break the symmetry ...
    full.signs, full.span = None, 2 * np.pi  # ... so force the full period
    w = np.array([speed])
    a, b = (ladder.solve(w, np.array([np.inf])) for ladder in (half, full))
    assert a.accepted[0] and b.accepted[0]
    system = periodyn.RheoLinear.from_functions(lambda t: np.eye(2), lambda t: 0.02 * np.eye(2),
                                                lambda t: _stiffness(speed * t, MU), lambda t: np.zeros(2),
                                                speed, 16)
    reference = periodyn.characteristic_exponents(system, 0, "monodromy")
    T = 2 * np.pi / speed
    for est in (a, b):
        got = np.sort(np.exp(est.exponents[0].real * T))
        want = np.sort(np.abs(reference.multipliers))
        assert abs(np.log(got[-1] / want[-1])) <= est.error[0] + 5e-9
        assert np.abs(got - want).max() / want[-1] <= est.error[0] + 5e-9
    assert a.steps[0] <= b.steps[0]
