"""The spatial beam through the whole element path (model builder, kinematics with Euler
parameters, linearization): the slider-crank of Schwab & Meijaard 2001 (section 4.2) built
from spatial beams reproduces the planar model's linearized equations, and a pinned shaft
built in a spatial model reproduces the frequencies of the element matrices assembled by
hand (tests/verification/test_spatial_beam_frequencies.py) and of beam theory, and spinning
it whirls like a gyroscopic Rayleigh beam."""

import numpy as np
import pytest
from scipy.linalg import eigh

from periodyn.errors import InputError
from periodyn.examples.slider_crank_rod import (CRANK_LENGTH, EI, MASS_PER_LENGTH, PLUNGER_MASS, ROD_LENGTH,
                                            slider_crank_model)
from periodyn.model.linearization import linearize
from periodyn.model import BeamSection, Model
from tests.verification.test_spatial_beam_frequencies import (E_MOD, L, NU, OMEGA_B, RADIUS, RHO, _torsion,
                                                              pinned_bending)

KELVIN_VOIGT = 2e-4


def spatial_slider_crank(rod_elements=2):
    """The planar example's mechanism in a spatial model: rigid crank beam driven by a
    hinge about z, a pin (hinge about z) at A, the rod of spatial beams whose in-plane
    bending modes are flexible (the rest rigid), the plunger's y fixed (its z follows)."""
    m = Model("spatial_slider_crank", dimension=3)
    m.add_orientation("ground")
    m.fix("ground")
    for node in ["crank", "crank_A"] + [f"rod_end{i}" for i in range(rod_elements + 1)]:
        m.add_orientation(node)
    m.add_hinge("main", ("ground", "crank"), axis=(0, 0, 1))
    m.prescribe("main.rotation", rate=1.0)
    m.add_point("O", (0.0, 0.0, 0.0))
    m.add_point("A", (CRANK_LENGTH, 0.0, 0.0))
    m.fix("O")
    m.add_spatial_beam("crank_arm", ("O", "A"), ("crank", "crank_A"), BeamSection(mass_per_length=MASS_PER_LENGTH))
    m.add_hinge("pin", ("crank_A", "rod_end0"), axis=(0, 0, 1))
    points = ["A"]
    for i in range(1, rod_elements + 1):
        points.append("B" if i == rod_elements else f"R{i}")
        m.add_point(points[-1], (CRANK_LENGTH + ROD_LENGTH * i / rod_elements, 0.0, 0.0))
    rod = BeamSection(EI_y=EI, EI_z=EI, mass_per_length=MASS_PER_LENGTH)
    for i in range(rod_elements):
        m.add_spatial_beam(f"rod{i + 1}", (points[i], points[i + 1]), (f"rod_end{i}", f"rod_end{i + 1}"), rod,
                           modes={"bending_z_p": "flexible", "bending_z_q": "flexible"}, kelvin_voigt=KELVIN_VOIGT)
    m.add_mass("B", PLUNGER_MASS)
    m.fix("B.y")
    return m.compile()


def test_spatial_slider_crank_linearizes_like_the_planar_one():
    planar, spatial = slider_crank_model(kelvin_voigt=KELVIN_VOIGT), spatial_slider_crank()
    assert spatial.dynamic_names == ("rod1.bending_z_p", "rod1.bending_z_q", "rod2.bending_z_p", "rod2.bending_z_q")
    omega, p = 250.0, 16
    a, b = linearize(planar, omega, p), linearize(spatial, omega, p)
    for name in ("mass", "damping", "stiffness", "additional_force", "applied_force"):
        got, want = getattr(b, name), getattr(a, name)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * np.abs(want).max(), err_msg=name)
    assert np.abs(a.stiffness).max() > 100.0 and np.abs(a.additional_force).max() > 1e-3   # not trivially equal


def spatial_shaft(n_el, lumped=False, spin=False):
    """The steel shaft along x in a spatial model: a universal joint at x = 0 (its twist
    held; with ``spin`` to a motor driving the shaft about its axis at constant speed,
    the joint at zero misalignment then being a pin that transmits the spin), both ends'
    lateral positions fixed, the far end free to slide axially; elements inextensible,
    the other five modes flexible (dynamic)."""
    m = Model("shaft", dimension=3)
    m.add_orientation("ground")
    m.fix("ground")
    support = "ground"
    if spin:
        support = m.add_orientation("drive")
        m.add_hinge("motor", ("ground", "drive"), axis=(1, 0, 0))
        m.prescribe("motor.rotation", rate=1.0)
    section = BeamSection.solid_circular(RADIUS, E_MOD, NU, RHO)
    for i in range(n_el + 1):
        m.add_point(f"P{i}", (i * L / n_el, 0.0, 0.0))
        m.add_orientation(f"R{i}")
    m.add_universal_joint("support", (support, "R0"), axes=[(0, 1, 0), (0, 0, 1)])
    flexible = {mode: "flexible" for mode in ("torsion", "bending_z_p", "bending_z_q", "bending_y_p", "bending_y_q")}
    for i in range(n_el):
        m.add_spatial_beam(f"shaft{i}", (f"P{i}", f"P{i + 1}"), (f"R{i}", f"R{i + 1}"), section, modes=flexible,
                           lumped_rotary=lumped)
    m.fix("P0")
    m.fix(f"P{n_el}.y")
    m.fix(f"P{n_el}.z")
    return m.compile()


@pytest.mark.parametrize("lumped", [False, True])
def test_shaft_model_frequencies_match_the_element_assembly(lumped):
    n_el = 4
    model = spatial_shaft(n_el, lumped)
    assert model.n_dynamic == 5 * n_el
    lin = linearize(model, 0.0, 1)
    w = np.sqrt(np.clip(eigh(lin.stiffness[0], lin.mass[0], eigvals_only=True), 0, None))
    bending = pinned_bending(n_el, rotary=True, lumped=lumped)
    np.testing.assert_allclose(w[:2], bending[:2], rtol=1e-9)
    assert w[0] == pytest.approx(OMEGA_B, rel=2e-3)   # Rayleigh beam, 4 elements
    torsion = _torsion(n_el, lumped, 0.0)                # clamped-free shaft, same elements
    assert np.min(np.abs(w / torsion - 1)) < 1e-9


def test_spatial_beam_needs_a_spatial_model():
    planar = Model("planar")
    with pytest.raises(InputError, match="add_spatial_beam"):
        planar.add_spatial_beam("b", ("p", "q"), ("Rp", "Rq"), BeamSection())
    spatial = Model("spatial", dimension=3)
    with pytest.raises(InputError, match="use add_spatial_beam"):
        spatial.add_beam("b", ("p", "q"), ("a", "b"))
    spatial.add_point("p", (0, 0, 0))
    with pytest.raises(InputError):
        spatial.add_spatial_beam("b", ("p", "missing"), ("Rp", "Rq"), BeamSection())


def test_spinning_shaft_whirls_like_a_gyroscopic_rayleigh_beam():
    """Linearized about the spin Omega, the equations in the beam's (co-rotating) modes are
    constant, and the first bending pair's frequencies are the simply supported spinning
    Rayleigh beam's whirl speeds seen from the rotating frame: forward w_f - Omega and
    backward w_b + Omega, with (rhoA + rhoI k^2) w^2 -/+ rhoJ k^2 Omega w - EI k^4 = 0,
    k = pi / L (gyroscopic, Coriolis and centrifugal terms of the beam's inertia)."""
    spin = 300.0
    sec = BeamSection.solid_circular(RADIUS, E_MOD, NU, RHO)
    k = np.pi / L
    a, g, s = sec.mass_per_length + sec.rotary_inertia_z * k**2, sec.polar_inertia * k**2 * spin, sec.EI_z * k**4
    forward = (g + np.sqrt(g**2 + 4 * a * s)) / (2 * a)
    backward = (-g + np.sqrt(g**2 + 4 * a * s)) / (2 * a)
    expected = np.array([forward - spin, backward + spin])
    errors = []
    for n_el in (4, 8):
        model = spatial_shaft(n_el, spin=True)
        lin = linearize(model, spin, 4)
        for name in ("mass", "damping", "stiffness"):
            sample = getattr(lin, name)
            np.testing.assert_allclose(sample, np.broadcast_to(sample[0], sample.shape), rtol=0,
                                       atol=1e-9 * np.abs(sample).max(), err_msg=name)
        M, C, K = lin.mass[0], lin.damping[0], lin.stiffness[0]
        n = M.shape[0]
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
        lam = np.linalg.eigvals(A)
        assert np.abs(lam.real).max() < 1e-6 * np.abs(lam).max()   # undamped, gyroscopic: no decay
        w = np.sort(lam.imag[lam.imag > 1.0])
        got = np.array([w[np.argmin(np.abs(w - e))] for e in expected])
        errors.append(np.abs(got / expected - 1).max())
    assert errors[1] < errors[0] and errors[1] < 3e-5
