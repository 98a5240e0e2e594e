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
from periodyn.system import OmegaSplitModel


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
                          (1e300, 0.0, 0.25 * math.pi, 1, "sparse", None)])
def test_overdamped_pendulum_stability_fails_with_a_reason(zeta, ecc, omega, harmonics, method, reason):
    """zeta = 1e3 at 0.2 omega0: exp(-2 zeta omega0 T) underflows the Magnus monodromy to a
    singular matrix; zeta = 1e300 (sparse Hill, a case the sweep-file property test drew):
    the harmonic balance overflows, or Hill's eigenvectors of a cluster spaced 1e-300 apart
    relative to its exponent are mixed (truncated), or the exponent is out of range: which
    stage loses the numbers first depends on the LAPACK build's rounding, so that case
    asks only for a failed point with a reason and no warning of numpy's."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        ds = sweep(pendulum(samples=24, zeta=zeta, eccentricity=ecc), [omega], harmonics, None, method,
                   progress=False)
    assert ds["status"].values.ravel().tolist() == [1] and not ds["stable"].values.any()
    message = str(ds["message"].values.ravel()[0])
    if reason is None:
        assert any(why in message for why in ("overflows", "truncated", "beyond the range")), message
    else:
        assert reason in message


def test_exponent_beyond_the_double_range_fails_with_a_reason():
    """q'' - 1e34 q = 0 at omega = 1 rad/s: lambda = 1e17 1/s exactly (constant coefficients),
    Re(lambda) T = 2 pi 1e17, whose multiplier exp(lambda T) is no double: the point fails
    and says so instead of reporting an infinite multiplier."""
    p = 8
    model = OmegaSplitModel.from_samples(np.ones((p, 1, 1)), [np.zeros((p, 1, 1))], [np.full((p, 1, 1), -1e34)],
                                         [np.zeros((p, 1))])
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        ds = sweep(model, [1.0], 2, None, "dense", progress=False)
    assert ds["status"].values.ravel().tolist() == [1] and not ds["stable"].values.any()
    assert "Re(lambda) T = 6.28e+17, beyond the range" in str(ds["message"].values.ravel()[0])
