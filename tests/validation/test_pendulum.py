"""Elliptic pendulum, Schwab & Meijaard (2001) sec. 4.1, eq. (29), Figs. 2-3.

The paper reads off its Fig. 3: stable for 0 <= w/w0 < 0.91 and 1.02 < w/w0 < 1.31,
transcritical instabilities at 0.91 and 1.02 and a Neimark-Hopf bifurcation near 1.31.
We find, confirmed by the monodromy matrix to 1e-6: boundaries at 0.9187 and 1.0233
(multiplier through +1, as the paper says) and the upper one at 1.3591 with a multiplier
through -1 (period doubling). For this one-degree-of-freedom equation with constant
damping the exponents always sum to -2 zeta w0 (Liouville), so a complex pair has real part
-zeta w0 < 0 and cannot cross the imaginary axis: a Neimark-Hopf bifurcation is impossible
here, and the paper's 1.31 is a figure reading of the period-doubling boundary.
"""

import numpy as np
import pytest

import periodyn
from periodyn.stability.boundaries import stability_boundaries


@pytest.fixture(scope="module")
def model():
    return periodyn.examples.pendulum(samples=32)


def test_omega_split_equals_direct_linearization(model):
    w0 = model.metadata["omega0"]
    z, e, rho = 0.01, 0.5, 0.5
    for w in (0.3 * w0, 1.1 * w0, 7.0):
        direct = periodyn.RheoLinear.from_functions(
            lambda t: 1.0, lambda t: 2 * z * w0, lambda t: w0**2 + (1 + e) * rho * w**2 * np.cos(w * t),
            lambda t: -2 * z * w0 * w + (1 - e) * rho * w**2 * np.sin(w * t), w, 32)
        split = model.at(w)
        for a, b in zip(split.spectra[:4], direct.spectra[:4]):
            np.testing.assert_allclose(a, b, atol=1e-12)
        np.testing.assert_allclose(split.stiffness, direct.stiffness, rtol=1e-14)


def test_stability_boundaries_hill_and_monodromy(model):
    w0 = model.metadata["omega0"]
    grid = np.linspace(0.5, 1.45, 20) * w0
    hill = stability_boundaries(model.at, grid, 12, "dense")
    mono = stability_boundaries(model.at, grid, 12, "monodromy")
    assert [b.kind for b in hill] == ["fold", "fold", "period-doubling"]
    assert [b.becomes_stable for b in hill] == [False, True, False]
    np.testing.assert_allclose([b.omega for b in hill], [b.omega for b in mono], rtol=1e-6)
    found = np.array([b.omega for b in hill]) / w0
    np.testing.assert_allclose(found, [0.9187, 1.0233, 1.3591], atol=1e-4)
    # the paper's figure readings for the two transcritical boundaries
    np.testing.assert_allclose(found[:2], [0.91, 1.02], atol=0.01)


def test_complex_exponents_keep_real_part_minus_zeta_w0(model):
    w0 = model.metadata["omega0"]
    for r in (0.2, 0.6, 1.2, 1.3, 1.33):
        ex = periodyn.characteristic_exponents(model.at(r * w0), 14)
        np.testing.assert_allclose(ex.exponents.real.sum(), -2 * 0.01 * w0, atol=1e-10)
        if np.all(np.abs(ex.principal.imag) > 1e-6) and np.all(np.abs(np.abs(ex.principal.imag) - r * w0 / 2) > 1e-6):
            np.testing.assert_allclose(ex.exponents.real, -0.01 * w0, atol=1e-10)


def test_resonance_near_half_and_third_of_w0(model):
    """Fig. 2: peaks at about w0/2 and w0/3 in 0 < w/w0 < 0.9."""
    w0 = model.metadata["omega0"]
    r = np.linspace(0.2, 0.85, 651)
    amp = np.array([periodyn.periodic_solution(model.at(x * w0), 12).amplitude()[0] for x in r])
    peaks = [i for i in range(1, r.size - 1) if amp[i] > amp[i - 1] and amp[i] > amp[i + 1]]
    near = lambda target: min(abs(r[i] - target) for i in peaks)  # noqa: E731
    assert near(0.5) < 0.02 and near(1 / 3) < 0.02
    main = max(peaks, key=lambda i: amp[i])
    assert abs(r[main] - 0.5) < 0.02


def test_linearized_equation_29_is_the_jacobian_of_equation_28(model):
    """Eq. (29) from eq. (28) at phi = 0: f = force(0, 0, t), K = -df/dq, C = -df/dq'."""
    dae = periodyn.examples.pendulum_nonlinear()
    w0 = model.metadata["omega0"]
    w = 0.7 * w0
    sys = model.at(w)
    for t in sys.times[::5]:
        q0, v0 = np.zeros((1, 1)), np.zeros((1, 1))
        f = dae.force(q0, v0, np.array([t]), w, dae.parameters)[0]
        dfdq, dfdv = (a[0] for a in dae.force_jacobians(q0, v0, np.array([t]), w, dae.parameters))
        j = int(round(t * w / (2 * np.pi) * sys.samples)) % sys.samples
        np.testing.assert_allclose(f, sys.force[j], atol=1e-12)
        np.testing.assert_allclose(-dfdq, sys.stiffness[j], atol=1e-12)
        np.testing.assert_allclose(-dfdv, sys.damping[j], atol=1e-12)


def test_full_nonlinear_orbit_by_shooting_approaches_the_linearized_one(model):
    """Away from resonance the non-linear (eq. 28) and linearized (eq. 29) periodic
    solutions differ by a relative O(amplitude^2): Fig. 2 solid vs dashed."""
    from periodyn.nonlinear.shooting_solver import shooting

    dae = periodyn.examples.pendulum_nonlinear()
    w0 = model.metadata["omega0"]
    for r in (0.2, 0.3):
        lin = periodyn.periodic_solution(model.at(r * w0), 12)
        nl = shooting(dae, r * w0)
        assert nl.residual < 1e-9
        rel = abs(nl.amplitude()[0] - lin.amplitude()[0]) / lin.amplitude()[0]
        assert rel < 2 * lin.amplitude()[0] ** 2
