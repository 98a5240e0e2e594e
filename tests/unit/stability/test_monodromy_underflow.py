"""A monodromy matrix that underflows (a mode decaying by more than 1e-308 per period) and
exponents whose multipliers overflow are failures with a reason, not log(0) warnings or
infinite multipliers at a solved point."""

import math
import warnings

import numpy as np
import pytest

from periodyn import sweep
from periodyn.errors import ConvergenceError
from periodyn.examples import pendulum
from periodyn.stability.monodromy import exponents_from_monodromy
from periodyn.stability.magnus import monodromy_exponent_array


def test_zero_multiplier_gives_nan_exponents_without_a_warning():
    Phi = np.array([[[0.5, 0.0], [0.0, 0.25]], [[0.5, 0.0], [0.0, 0.0]]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lam = monodromy_exponent_array(Phi, np.array([2 * np.pi, 2 * np.pi]))
        with pytest.raises(ConvergenceError, match="singular"):
            exponents_from_monodromy(Phi[1], 2 * np.pi, "magnus")
    np.testing.assert_allclose(np.sort(lam[0].real), np.log([0.25, 0.5]), rtol=1e-14)
    assert np.isnan(lam[1]).all()


@pytest.mark.parametrize("zeta,ecc,omega,harmonics,method,reason",
                         [(1e3, 0.5, 0.2 * math.sqrt(9.81), 2, "magnus", "singular"),
                          (1e300, 0.0, 0.25 * math.pi, 1, "sparse", "beyond the range")])
def test_overdamped_pendulum_stability_fails_with_a_reason(zeta, ecc, omega, harmonics, method, reason):
    """zeta = 1e3 at 0.2 omega0: exp(-2 zeta omega0 T) underflows the Magnus monodromy to a
    singular matrix; zeta = 1e300 (sparse Hill, a case the sweep-file property test drew)
    gives an exponent with Re(lambda) T ~ 6e13."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        ds = sweep(pendulum(samples=24, zeta=zeta, eccentricity=ecc), [omega], harmonics, None, True, method,
                   progress=False)
    assert ds["status"].values.ravel().tolist() == [1] and not ds["stable"].values.any()
    assert reason in str(ds["message"].values.ravel()[0])
