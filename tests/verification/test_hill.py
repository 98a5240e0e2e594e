"""Characteristic exponents by Hill's method against the Mathieu stability chart
(scipy.special.mathieu_a/b), the monodromy matrix from direct integration, and the
dense solver (for the sparse subset)."""

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import mathieu_a, mathieu_b

import periodyn
from periodyn import TruncationWarning

from ..conftest import assert_same_spectrum, mathieu, two_dof_parametric


def trace_of_monodromy(a, q, m=20):
    """Re(mu1 + mu2) from Hill's exponents of x'' + (a - 2q cos 2t) x = 0."""
    ex = periodyn.characteristic_exponents(mathieu(a, q, samples=64), m, "dense")
    return ex.multipliers.sum().real


# boundary curve, its tabulated value, and the multiplier on it (+1: period pi, -1: 2 pi)
CURVES = [("a0", lambda q: mathieu_a(0, q), +1), ("b1", lambda q: mathieu_b(1, q), -1),
          ("a1", lambda q: mathieu_a(1, q), -1), ("b2", lambda q: mathieu_b(2, q), +1),
          ("a2", lambda q: mathieu_a(2, q), +1)]


@pytest.mark.parametrize("q", [0.5, 1.0, 2.0])
@pytest.mark.parametrize("name,curve,mu", CURVES, ids=[c[0] for c in CURVES])
def test_mathieu_stability_boundaries(name, curve, mu, q):
    """On a boundary curve tr(Phi) = 2 mu: locate the root from Hill's multipliers."""
    a_ref = curve(q)
    f = lambda a: trace_of_monodromy(a, q) - 2 * mu  # noqa: E731
    grid = np.linspace(a_ref - 0.02, a_ref + 0.02, 9)
    vals = np.array([f(a) for a in grid])
    roots = [brentq(f, grid[j], grid[j + 1], xtol=1e-13) for j in range(8) if vals[j] * vals[j + 1] < 0]
    assert roots, f"no sign change of tr(Phi) - 2mu near {name}({q})"
    a_hill = min(roots, key=lambda r: abs(r - a_ref))
    assert abs(a_hill - a_ref) < 1e-6, (name, q, a_hill, a_ref)


@pytest.mark.parametrize("a,q,zeta", [(1.0, 0.3, 0.05), (1.2, 0.8, 0.02), (3.8, 1.5, 0.1), (-0.3, 0.6, 0.01)])
def test_damped_mathieu_hill_equals_monodromy(a, q, zeta):
    sys = mathieu(a, q, samples=64, zeta=zeta)
    hill = periodyn.characteristic_exponents(sys, 16, "dense")
    mono = periodyn.characteristic_exponents(sys, 16, "monodromy")
    assert_same_spectrum(hill.multipliers, mono.multipliers, atol=1e-9)
    # Liouville: the exponents sum to -2 zeta (trace of the first-order matrix)
    assert abs(hill.exponents.sum().real + 2 * zeta) < 1e-10
    assert hill.stable == mono.stable


def test_two_dof_combination_resonance_complex_exponents():
    """Sum-type combination resonance w ~ w1 + w2 = 3.3: a complex pair of multipliers
    leaves the unit circle (neither +1 nor -1)."""
    sys = two_dof_parametric(omega=3.3, eps=0.6, samples=64)
    hill = periodyn.characteristic_exponents(sys, 16, "dense")
    sparse = periodyn.characteristic_exponents(sys, 16, "sparse")
    mono = periodyn.characteristic_exponents(sys, 16, "monodromy")
    assert_same_spectrum(hill.multipliers, mono.multipliers, atol=1e-8)
    assert_same_spectrum(sparse.exponents, hill.exponents, atol=1e-9)
    assert not hill.stable and not mono.stable
    crit = hill.multipliers[np.argmax(hill.exponents.real)]
    assert abs(crit) > 1 and 0.05 * np.pi < abs(np.angle(crit)) < 0.95 * np.pi
    from periodyn.stability.boundaries import crossing_type

    assert crossing_type(hill) == "neimark-sacker"


@pytest.mark.parametrize("omega", [0.7, 1.3, 2.0, 4.1])
def test_hill_forms_and_methods_agree_with_monodromy(omega):
    sys = two_dof_parametric(omega=omega)
    mono = periodyn.characteristic_exponents(sys, 0, "monodromy").multipliers
    for form in ("direct", "inverse-mass"):
        for method in ("dense", "sparse"):
            ex = periodyn.characteristic_exponents(sys, 14, method, form=form)
            assert_same_spectrum(ex.multipliers, mono, atol=1e-8)


def test_centred_representative_is_the_physical_frequency():
    """Weak parametric excitation: the chosen exponents sit at +-i w_n, not folded into
    the strip |Im| <= w/2 as the principal logarithm of the monodromy method is."""
    sys = mathieu(a=9.0, q=0.05, zeta=0.01)  # w_n = 3 = 1.5 omega
    ex = periodyn.characteristic_exponents(sys, 12, "dense")
    np.testing.assert_allclose(np.sort(np.abs(ex.exponents.imag)), [3.0, 3.0], rtol=1e-3)
    assert np.all(np.abs(ex.principal.imag) <= 1.0 + 1e-12)
    assert np.all(np.abs(ex.centroid) < 0.5)


def test_edge_energy_indicates_truncation_error():
    """Strong parametric excitation: with few harmonics the chosen eigenvectors reach the
    truncation edge and the exponents are wrong; the edge indicator says so."""
    sys = mathieu(a=1.0, q=4.0, zeta=0.01, samples=64)
    mono = periodyn.characteristic_exponents(sys, 0, "monodromy")
    with pytest.raises(periodyn.ConvergenceError, match="truncated"):
        periodyn.characteristic_exponents(sys, 2, "dense")
    with pytest.warns(TruncationWarning, match="harmonics = 2"):
        coarse = periodyn.characteristic_exponents(sys, 2, "dense", truncation="warn")
    fine = periodyn.characteristic_exponents(sys, 20, "dense")
    assert coarse.edge.max() == coarse.truncation > 1e-3
    assert fine.edge.max() < 1e-12
    assert_same_spectrum(fine.multipliers, mono.multipliers, atol=1e-8)
    assert np.abs(np.sort(coarse.exponents.real) - np.sort(mono.exponents.real)).max() > 1e-3


@pytest.mark.parametrize("omega", [0.7, 2.0, 4.1])
def test_magnus_monodromy_matches_the_adaptive_reference(omega):
    """4th-order Magnus (fixed steps) against DOP853 at rtol 1e-11, and its convergence order."""
    from periodyn.stability.monodromy import monodromy_exponents

    sys = two_dof_parametric(omega=omega, samples=64)
    ref = periodyn.characteristic_exponents(sys, 0, "monodromy").multipliers
    errs = []
    for steps in (64, 128, 256):
        mu = monodromy_exponents(sys, "magnus", steps=steps).multipliers
        cost = np.abs(mu[:, None] - ref[None, :])
        errs.append(cost.min(axis=1).max())
    assert errs[-1] < 1e-8
    assert errs[1] < errs[0] / 8 and errs[2] < errs[1] / 8  # fourth order: about 16x per halving
