"""The 4th- and 6th-order Magnus monodromies: measured convergence order (slope of log
error against log h, the DOP853 monodromy at rtol 1e-11 as reference), and the certified
ladder's error estimate against that reference on the pendulum, the slider-crank and the
Cardan shaft (half-period ladder)."""

import numpy as np
import pytest

import periodyn
from periodyn.stability.floquet import STABILITY_TOL
from periodyn.kernels.solvers.floquet import magnus_monodromies
from periodyn.stability.magnus import MagnusLadder, gauss_angles, magnus_terms
from periodyn.numerics.spectra import synthesize
from periodyn.stability.monodromy import monodromy_matrix


def _magnus_monodromy(model, omega, steps, points):
    """Unbalanced Magnus monodromy (2n, 2n) of an omega-split model at one speed."""
    terms, a = magnus_terms(*(synthesize(X, gauss_angles(steps, points=points)) for X in model._power_spectra[:3]))
    phi = np.empty((1, 2 * model.n, 2 * model.n))
    magnus_monodromies(terms, np.array([omega]), phi, points)
    n = model.n
    phi[0, :n, n:] /= a
    phi[0, n:, :n] *= a
    return phi[0]


@pytest.mark.parametrize("points,order", [(2, 4), (3, 6)])
def test_measured_order_of_the_magnus_monodromy(points, order):
    model = periodyn.examples.pendulum(samples=64)
    omega = 0.7 * model.metadata["omega0"]
    reference = monodromy_matrix(model.at(omega))
    steps = np.array([16, 32, 64]) if order == 6 else np.array([32, 64, 128])
    errors = np.array([np.abs(_magnus_monodromy(model, omega, N, points) - reference).max() for N in steps])
    slopes = -np.diff(np.log(errors)) / np.log(2.0)  # error ~ h^order, h = T / N
    assert errors[-1] < 1e-7
    np.testing.assert_allclose(slopes, order, atol=0.3)


def _check_against_reference(model, ladder, speeds):
    est = ladder.solve(speeds, np.full(speeds.size, np.inf))
    assert est.accepted.all()
    for w, exps, error in zip(speeds, est.exponents, est.error):
        reference = periodyn.characteristic_exponents(model.at(w), 0, "monodromy")
        got = np.sort(np.exp(exps.real * 2 * np.pi / w))
        want = np.sort(np.abs(reference.multipliers))
        # the DOP853 reference (rtol 1e-11 per step) is itself good to a few 1e-9 per period
        assert abs(np.log(got[-1] / want[-1])) <= error + 5e-9
        assert np.abs(got - want).max() / want[-1] <= error + 5e-9
        assert error <= STABILITY_TOL * max(1.0, abs(np.log(want[-1])))
    return est


@pytest.mark.parametrize("order", [6, 4])
def test_certified_error_is_honest_on_pendulum_and_slider_crank(order):
    pendulum = periodyn.examples.pendulum(samples=64)
    speeds = np.array([0.2, 0.55, 0.7, 0.95, 1.1]) * pendulum.metadata["omega0"]  # 0.95: an unstable band
    _check_against_reference(pendulum, MagnusLadder(*pendulum._power_spectra[:3], order=order), speeds)
    crank = periodyn.examples.slider_crank(damping=0.02, samples=64)
    _check_against_reference(crank, MagnusLadder(*crank._power_spectra[:3], order=order),
                             np.array([150.0, 205.0, 268.0, 300.0]))


def test_certified_error_is_honest_on_the_cardan_shaft():
    model = periodyn.examples.cardan_shaft()
    ladder = MagnusLadder(*model._power_spectra[:3])
    assert ladder.span == np.pi and ladder.orders == (6, 4)  # half-period ladder, both orders
    wb = model.metadata["omega_b"]
    est = _check_against_reference(model, ladder, np.array([0.3, 0.66, 0.85]) * wb)  # 0.66, 0.85: unstable zones
    assert (est.order == 6).all() and (est.steps <= 256).all()  # fewer speeds than pilots: order 6 only
