"""Bad input gets a clear periodyn.InputError naming the problem, never a numpy traceback."""

import numpy as np
import pytest

import periodyn
from periodyn import InputError


def ok(p=16, n=2):
    return (np.broadcast_to(np.eye(n), (p, n, n)), np.zeros((p, n, n)), np.broadcast_to(np.eye(n), (p, n, n)),
            np.zeros((p, n)))


def test_wrong_shapes():
    M, C, K, f = ok()
    with pytest.raises(InputError, match="shape"):
        periodyn.RheoLinear.from_samples(M[0, 0], C, K, f, 1.0)
    with pytest.raises(InputError, match="same sample count"):
        periodyn.RheoLinear.from_samples(M, C[:5], K, f, 1.0)
    with pytest.raises(InputError, match="coordinates"):
        periodyn.RheoLinear.from_samples(M, C, K, np.zeros((16, 3)), 1.0)


def test_nan_and_inf_name_the_sample():
    M, C, K, f = ok()
    K = K.copy()
    K[3, 0, 0] = np.nan
    with pytest.raises(InputError, match="K has NaN or inf at sample 3"):
        periodyn.RheoLinear.from_samples(M, C, K, f, 1.0)


def test_singular_mass_names_the_sample():
    M, C, K, f = ok()
    M = M.copy()
    M[5] = [[1.0, 1.0], [1.0, 1.0]]
    with pytest.raises(InputError, match="singular at sample 5"):
        periodyn.RheoLinear.from_samples(M, C, K, f, 1.0)


@pytest.mark.parametrize("omega", [0.0, -1.0, np.inf, "fast"])
def test_bad_omega(omega):
    with pytest.raises(InputError, match="omega"):
        periodyn.RheoLinear.from_samples(*ok(), omega)


@pytest.mark.parametrize("m", [-1, 1.5, True])
def test_bad_harmonics(m):
    sys = periodyn.RheoLinear.from_samples(*ok(), 1.0)
    with pytest.raises(InputError, match="harmonics"):
        periodyn.periodic_solution(sys, m)


def test_samples_too_small_for_the_harmonics():
    sys = periodyn.RheoLinear.from_samples(*ok(p=8), 1.0)
    with pytest.raises(InputError, match="samples >= 11"):
        periodyn.periodic_solution(sys, 5)


def test_unresolved_coefficients_warn_about_aliasing():
    sys = periodyn.RheoLinear.from_functions(lambda t: 1.0, lambda t: 0.0, lambda t: 2 + np.abs(np.sin(t)),
                                             lambda t: np.cos(t), 1.0, 12)
    with pytest.warns(periodyn.AliasingWarning, match="increase samples"):
        periodyn.periodic_solution(sys, 3)


def test_round_off_coefficients_do_not_warn():
    """An undamped slider-crank's omega-term of the damping is round-off (~1e-18): its
    'spectrum' is noise and must not raise an aliasing alarm."""
    import warnings

    from periodyn.speeds import SpeedSolver
    from periodyn.examples.slider_crank_rod import slider_crank_model
    from periodyn.model.linearization import omega_split

    with warnings.catch_warnings():
        warnings.simplefilter("error", periodyn.AliasingWarning)
        SpeedSolver(omega_split(slider_crank_model(), 64), 12, stability=False).solve(200.0)


def test_unknown_options():
    sys = periodyn.RheoLinear.from_samples(*ok(), 1.0)
    with pytest.raises(InputError, match="form"):
        periodyn.periodic_solution(sys, 2, form="inverse")
    with pytest.raises(InputError, match="method"):
        periodyn.characteristic_exponents(sys, 2, method="qr")
    with pytest.raises(InputError, match="callable"):
        periodyn.RheoLinear.from_functions(np.eye(2), lambda t: 0, lambda t: 0, lambda t: 0, 1.0, 8)


def test_complex_coefficients_are_refused_not_truncated():
    """A complex mass used to lose its imaginary part silently."""
    M, C, K, f = ok()
    with pytest.raises(InputError, match="M must be real, got complex"):
        periodyn.RheoLinear.from_samples(M * (1 + 0.5j), C, K, f, 1.0)
    with pytest.raises(InputError, match="must be real, got complex"):
        periodyn.RheoLinear.from_functions(lambda t: 1.0 + 1j, lambda t: 0.0, lambda t: 1.0, lambda t: 0.0, 1.0, 8)
    with pytest.raises(InputError, match=r"damping\[omega\^0\] must be real"):
        periodyn.OmegaSplitModel.from_samples(M, [C + 1j], [K], [f])


def test_empty_coefficient_arrays_are_refused():
    with pytest.raises(InputError, match="at least one sample"):
        periodyn.RheoLinear.from_samples(*ok(p=0), 1.0)
    with pytest.raises(InputError, match="at least one sample and one coordinate"):
        periodyn.RheoLinear.from_samples(*ok(n=0), 1.0)
    with pytest.raises(InputError, match="at least one sample"):
        periodyn.OmegaSplitModel.from_samples(np.zeros((0, 1, 1)), [], [], [])
