"""Eigenfrequencies of a straight steel shaft assembled from spatial beam elements,
linearized about the straight configuration, against analytic beam and shaft theory
(the Cardan shaft of Schwab & Meijaard 2001, section 4.4: L = 1 m, r = 0.03 m,
rho = 7850 kg/m^3, E = 210 GPa, nu = 0.3)."""

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.optimize import brentq

from periodyn.kernels.elements import spatial_beam
from periodyn.kernels.elements.vector_inertia import add_vector_inertia
from periodyn.kernels.elements import jets
from periodyn.model.spatial_beam import BeamSection, SpatialBeam

L, RADIUS, RHO, E_MOD, NU = 1.0, 0.03, 7850.0, 210e9, 0.3
G_MOD = E_MOD / (2 * (1 + NU))
AREA = np.pi * RADIUS**2
I_AREA = np.pi * RADIUS**4 / 4
J_AREA = 2 * I_AREA
I_OUTPUT = 0.345555   # kg m^2, the paper's output inertia
OMEGA_B = np.pi**2 * np.sqrt(E_MOD * I_AREA / (RHO * AREA * L**4))   # 765.71 rad/s


def shaft(rotary: bool, lumped: bool) -> SpatialBeam:
    section = BeamSection.solid_circular(RADIUS, E_MOD, NU, RHO, rotary_inertia=rotary)
    return SpatialBeam("shaft", ("p", "q"), ("Rp", "Rq"), ("flexible",) * 6, section, lumped_rotary=lumped)


def assemble(beam: SpatialBeam, n_el: int, end_inertia: float = 0.0):
    """Global stiffness ``sum D_x^T S D_x`` and mass matrices (7 (n_el+1) coordinates) of
    a straight shaft along x with n_el elements, at rest in the reference configuration;
    end_inertia (kg m^2) a disk about x at the last node."""
    n_x = 7 * (n_el + 1)
    h = L / n_el
    K, M = np.zeros((n_x, n_x)), np.zeros((n_x, n_x))
    x = np.zeros(n_x)
    for node in range(n_el + 1):
        x[7 * node] = node * h
        x[7 * node + 3] = 1.0
    nd = spatial_beam.NDOF
    for e in range(n_el):
        sl = slice(7 * e, 7 * e + nd)
        xe = x[sl]
        par = beam.parameters(xe)
        D, Dx, Dxx, Dxxx = np.zeros(6), np.zeros((6, nd)), np.zeros((6, nd, nd)), np.zeros((6, nd, nd, nd))
        spatial_beam.deformation(xe, par, D, Dx, Dxx, Dxxx)
        assert np.abs(D).max() < 1e-15
        K[sl, sl] += Dx.T @ beam.stiffness_matrix(par[0]) @ Dx
        Me, re, Ce, Ke = np.zeros((nd, nd)), np.zeros(nd), np.zeros((nd, nd)), np.zeros((nd, nd))
        spatial_beam.inertia(xe, np.zeros(nd), np.zeros(nd), beam.inertia_parameters(par), np.zeros(3),
                             Me, re, Ce, Ke)
        assert not re.any() and not Ce.any()
        M[sl, sl] += Me
    if end_inertia:
        # a disk: rotary energy of its body axes y, z with second moments I/2 each
        o = 7 * n_el
        m = jets.size(4)
        g = np.zeros((2, 3, m))
        R = np.zeros((3, 3, m))
        jets.rotation_seeded(x[o + 3:o + 7], 0, R)
        g[0], g[1] = R[:, 1], R[:, 2]
        Md, r4, C4, K4 = np.zeros((4, 4)), np.zeros(4), np.zeros((4, 4)), np.zeros((4, 4))
        add_vector_inertia(g, 0.5 * end_inertia * np.eye(2), np.zeros(2), np.zeros(4), np.zeros(4),
                           np.zeros(3), Md, r4, C4, K4)
        M[o + 3:o + 7, o + 3:o + 7] += Md
    return K, M


def geometric_stiffness(beam, n_el, mode):
    """``sum D_xx[mode]`` over the elements of the straight shaft: the geometric stiffness
    of a unit stress on that mode in every element."""
    nd = spatial_beam.NDOF
    n_x = 7 * (n_el + 1)
    Kg = np.zeros((n_x, n_x))
    for e in range(n_el):
        xe = np.zeros(nd)
        xe[[0, 7]] = e * L / n_el, (e + 1) * L / n_el
        xe[[3, 10]] = 1.0
        D, Dx, Dxx, Dxxx = np.zeros(6), np.zeros((6, nd)), np.zeros((6, nd, nd)), np.zeros((6, nd, nd, nd))
        spatial_beam.deformation(xe, beam.parameters(xe), D, Dx, Dxx, Dxxx)
        Kg[7 * e:7 * e + nd, 7 * e:7 * e + nd] += Dxx[mode]
    return Kg


def frequencies(K, M, keep):
    """Undamped eigenfrequencies (rad/s) on the coordinates ``keep``."""
    w2 = eigh(K[np.ix_(keep, keep)], M[np.ix_(keep, keep)], eigvals_only=True)
    return np.sqrt(np.clip(w2, 0.0, None))


def pinned_bending(n_el, rotary=False, lumped=False):
    """Lowest bending frequencies of the pinned-pinned shaft: positions of both end nodes
    fixed, lam_0 of every node dropped (normalization: d lam . lam = d lam_0 = 0)."""
    K, M = assemble(shaft(rotary, lumped), n_el)
    n_x = K.shape[0]
    keep = [i for i in range(n_x) if i % 7 != 3 and not (i < 3 or n_x - 7 <= i < n_x - 4)]
    w = frequencies(K, M, keep)
    return w[w > 1.0]


def test_pinned_shaft_bending_converges_to_euler_bernoulli():
    assert OMEGA_B == pytest.approx(766.0, abs=0.5)   # the paper rounds 765.71 to 766
    errors = []
    for n_el in (2, 4, 8):
        w = pinned_bending(n_el)
        assert w[1] == pytest.approx(w[0], rel=1e-10)      # two equal planes (round section)
        errors.append(w[0] / OMEGA_B - 1.0)
    assert errors[0] > errors[1] > errors[2] > 0.0          # from above, as a displacement method
    assert errors[2] < 2e-5
    assert np.log2(errors[1] / errors[2]) > 3.5              # fourth-order convergence of Hermite cubics
    # the second bending frequency 4 omega_b
    assert pinned_bending(8)[2] == pytest.approx(4 * OMEGA_B, rel=1e-3)


@pytest.mark.parametrize("lumped", [False, True])
def test_pinned_shaft_with_rotary_inertia_converges_to_rayleigh_beam(lumped):
    """Simply supported Rayleigh beam: omega^2 = EI k^4 / (rhoA (1 + (I/A) k^2)), k = pi/L."""
    k = np.pi / L
    rayleigh = np.sqrt(E_MOD * I_AREA * k**4 / (RHO * AREA * (1 + I_AREA / AREA * k**2)))
    w = [pinned_bending(n, rotary=True, lumped=lumped)[0] for n in (4, 16)]
    assert rayleigh < OMEGA_B
    assert abs(w[1] / rayleigh - 1) < abs(w[0] / rayleigh - 1)
    assert w[1] == pytest.approx(rayleigh, rel=2e-5 if not lumped else 1e-4)


def _torsion(n_el, lumped, end_inertia):
    """Lowest torsional frequency of a shaft clamped at x = 0 with a disk at x = L:
    only the rotations about the axis (lam_1 of nodes 1..n_el) are kept, after checking
    that they decouple from every other coordinate at the straight configuration."""
    K, M = assemble(shaft(rotary=True, lumped=lumped), n_el, end_inertia)
    n_x = K.shape[0]
    keep = [7 * node + 4 for node in range(1, n_el + 1)]
    rest = [i for i in range(7, n_x) if i not in keep]   # node 0 is clamped
    assert np.abs(K[np.ix_(keep, rest)]).max() < 1e-9 * np.abs(K).max()
    assert np.abs(M[np.ix_(keep, rest)]).max() < 1e-15
    return frequencies(K, M, keep)[0]


@pytest.mark.parametrize("lumped", [False, True])
def test_torsion_with_end_inertia_converges_to_the_shaft_equation(lumped):
    """Clamped shaft with a disk I_d at the free end: beta tan beta = rho J L / I_d,
    omega = beta sqrt(G / rho) / L."""
    ratio = RHO * J_AREA * L / I_OUTPUT
    beta = brentq(lambda b: b * np.tan(b) - ratio, 1e-6, np.pi / 2 - 1e-9)
    exact = beta * np.sqrt(G_MOD / RHO) / L
    errors = [abs(_torsion(n, lumped, I_OUTPUT) / exact - 1) for n in (2, 4, 8)]
    assert errors[2] < errors[1] < errors[0]
    assert np.log2(errors[1] / errors[2]) > 1.9         # second order: linear twist interpolation
    assert errors[2] < (3e-7 if not lumped else 5e-5)


def test_paper_output_inertia_sets_torsion_to_bending_over_root_two():
    """Section 4.4: I_o makes the first torsional frequency of the shaft with lumped rotary
    inertia equal omega_b / sqrt(2) (one element: stiffness GJ/L against I_o + rhoJ L / 2)."""
    assert _torsion(1, True, I_OUTPUT) == pytest.approx(OMEGA_B / np.sqrt(2), rel=1e-5)


def inverse_critical_stresses(n_el, mode, hold_end_twist):
    """Eigenvalues 1/s of ``(K + s Kg) phi = 0``, Kg the geometric stiffness of a unit stress
    on ``mode`` in every element: ends pinned, the twist of node 0 held (and of the last
    node if hold_end_twist), lam_0 dropped as for the frequencies."""
    beam = shaft(rotary=False, lumped=False)
    K, _ = assemble(beam, n_el)
    Kg = geometric_stiffness(beam, n_el, mode)
    n_x = K.shape[0]
    last = n_x - (2 if hold_end_twist else 4)
    keep = [i for i in range(n_x) if i % 7 != 3 and not (i < 5 or n_x - 7 <= i < last)]
    return eigh(-Kg[np.ix_(keep, keep)], K[np.ix_(keep, keep)], eigvals_only=True)


def test_pinned_column_buckles_at_the_euler_load():
    """Geometric stiffness from axial force: with the compressive force P in every element
    (initial stress -P on the elongation), ``K + sum sigma D_xx`` turns singular at
    P = pi^2 EI / L^2 as the mesh is refined, in both bending planes."""
    euler = np.pi**2 * E_MOD * I_AREA / L**2
    errors = []
    for n_el in (2, 4, 8):
        inverse = inverse_critical_stresses(n_el, 0, hold_end_twist=False)
        loads = np.sort(1.0 / -inverse[inverse < -1e-12])   # compressive: s = -P < 0
        assert loads[1] == pytest.approx(loads[0], rel=1e-9)   # both planes
        errors.append(loads[0] / euler - 1)
    assert errors[0] > errors[1] > errors[2] > 0.0
    assert errors[0] == pytest.approx(0.0075, abs=1e-4)   # the textbook 0.75 % of two cubic elements
    assert np.log2(errors[1] / errors[2]) > 3.5 and errors[2] < 4e-5


def test_torqued_shaft_buckles_at_the_continuum_torque():
    """Geometric stiffness from torque: a pinned shaft with its end twists held (lam_1 = 0:
    the rotation vectors' axial components vanish) under the torque T in every element
    (initial stress on the torsion mode). The torsion mode is the integral of the
    sections' torsional curvature, so the continuum energy of the buckling mode
    u = v + i w is ``1/2 EI int |u''|^2 - T/2 int Im(conj(u') u'')``; its Euler equation
    EI u'''' = i T u''' with u = 0 and EI u'' = (i T / 2) u' at both ends gives
    T = x EI / L with tan(x / 2) = -x / 6 (x = 4.9113)."""
    y = brentq(lambda y: np.tan(y) + y / 3, np.pi / 2 + 1e-6, np.pi - 1e-9)
    critical = 2 * y * E_MOD * I_AREA / L
    errors = []
    for n_el in (4, 8, 16):
        inverse = inverse_critical_stresses(n_el, 1, hold_end_twist=True)
        torques = np.sort(1.0 / np.abs(inverse[np.abs(inverse) > 1e-14]))
        assert torques[1] == pytest.approx(torques[0], rel=1e-9)   # either sense of the torque
        errors.append(torques[0] / critical - 1)
    assert errors[0] > errors[1] > errors[2] > 0.0
    assert np.log2(errors[1] / errors[2]) > 3.5 and errors[2] < 2e-5
