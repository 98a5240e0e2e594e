"""FloquetExponents and the one stability verdict (periodyn.stability.floquet)."""

import numpy as np

from periodyn.stability.floquet import STABILITY_TOL, FloquetExponents, is_stable
from periodyn.stability.hill import FloquetExponents as FromHill


def test_from_multipliers_round_trip_and_period():
    """Exponents log(mu)/T of given multipliers give them back; T = 2 pi nu / omega."""
    mu = np.array([0.5 + 0.5j, 0.5 - 0.5j, -0.9, 1.2])
    for nu in (1, 2):
        fl = FloquetExponents.from_multipliers(mu, 3.0, "test", subharmonic=nu)
        assert fl.period == 2 * np.pi * nu / 3.0
        np.testing.assert_allclose(fl.multipliers, mu, rtol=1e-14)
        np.testing.assert_allclose(np.exp(fl.principal * fl.period), mu, rtol=1e-14)
        assert np.all(np.abs(fl.principal.imag) <= np.pi / fl.period * (1 + 1e-14))
        assert fl.max_multiplier == 1.2 and not fl.stable
        assert np.isclose(fl.max_real, np.log(1.2) / fl.period, rtol=1e-14)
        assert np.isnan(fl.centroid).all() and np.isnan(fl.edge).all()
    assert FromHill is FloquetExponents  # the old import path still works


def test_verdict_is_growth_per_period():
    """Stable iff log max|mu| <= tol: a neutral multiplier (conservative system) is stable,
    a growth of 10 tol per period is not, and the verdict does not depend on the speed."""
    for omega in (0.1, 1.0, 1e3):
        neutral = FloquetExponents.from_multipliers([np.exp(0.3j), np.exp(-0.3j)], omega, "test")
        growing = FloquetExponents.from_multipliers([np.exp(10 * STABILITY_TOL), 0.5], omega, "test")
        decaying = FloquetExponents.from_multipliers([0.999, 0.2], omega, "test")
        assert neutral.stable and not growing.stable and decaying.stable
    # the former DAE rule |mu| <= 1 + 1e-6 gives the same verdicts outside a 1e-12 window
    for mu in (1 + 0.99e-6, 1 + 1.01e-6, 0.5, 2.0):
        assert FloquetExponents.from_multipliers([mu], 2.0, "t").stable == (mu <= 1 + 1e-6)
    assert list(is_stable(np.array([-1.0, np.nan, 1.0]), 1.0)) == [True, False, False]
    assert FloquetExponents.from_multipliers([], 1.0, "t").stable
