"""Mean-system modal reduction of element models (periodyn.model.reduce)."""

import numpy as np
import pytest

from periodyn import characteristic_exponents, periodic_solution
from periodyn.errors import InputError
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
from periodyn.model.linearization import omega_split
from periodyn.model.reduce import MeanModes, guarded_modes, mean_modes, modal_reduction, modal_spectrum
from periodyn.numerics.spectra import fourier_coefficients
from periodyn.stability.magnus import MagnusLadder


def crank(elements: int, damping: float = 0.02, samples: int = 64):
    """The slider-crank with ``elements`` rod elements, ``damping`` of critical in its first mode."""
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=elements))
    return omega_split(slider_crank_model(2 * damping / w1, rod_elements=elements), samples,
                       rebuild=lambda p: crank(elements, damping, p))


@pytest.fixture(scope="module")
def crank4():
    return crank(4)


def test_all_modes_reproduce_the_full_model(crank4):
    """k = n is a change of coordinates: the resolved fixed-step Magnus exponents (a
    similarity of the monodromy; the stiff rod modes decay by more than the steps resolve)
    and the forced response are the full model's to round-off."""
    red = modal_reduction(crank4, crank4.n)
    for w in (170.0, 260.0):
        full = characteristic_exponents(crank4.at(w), 12, "magnus").exponents
        mine = characteristic_exponents(red.at(w), 12, "magnus").exponents
        slow = np.abs(full.real) * 2 * np.pi / w < 10
        assert slow.sum() >= 4
        assert np.allclose(mine[slow], full[slow], rtol=1e-10, atol=1e-10 * np.abs(full[slow]).max())
        qf = periodic_solution(crank4.at(w), 12).harmonics
        qr = red.physical(periodic_solution(red.at(w), 12).harmonics)
        assert np.allclose(qr, qf, rtol=0, atol=1e-9 * np.abs(qf).max())


def test_the_basis_is_mass_orthonormal_and_kept(crank4):
    mm = mean_modes(crank4)
    M = crank4.mass.mean(axis=0)
    assert np.allclose(mm.shapes.T @ M @ mm.shapes, np.eye(crank4.n), atol=1e-10)
    assert np.all(np.diff(mm.frequencies) > 0) and abs(mm.frequencies[0] / first_bending_frequency(
        slider_crank_model(0.0, rod_elements=4)) - 1) < 0.05
    red = modal_reduction(crank4, 3)
    assert red.n == 3 and red.basis.shape == (crank4.n, 3) and red.full is crank4
    assert red.output_names == crank4.output_names and red.with_samples(48).basis is red.basis
    assert red.with_samples(48).samples == 48


def test_reduced_exponents_converge_with_the_rod_mesh():
    """The 4-mode reductions of 16, 32 and 64-element rods: log max|mu| differences fall
    at least 8x per mesh halving (beam elements converge as h^4) and are below 1e-7
    from 32 to 64 elements, while the cost stays that of a 4-mode model."""
    w = np.array([160.0, 240.0])
    growth = []
    for el in (16, 32, 64):
        red = modal_reduction(crank(el), 4)
        est = MagnusLadder(*red._power_spectra[:3]).solve(w, np.inf)
        assert est.accepted.all()
        growth.append(est.exponents.real.max(axis=1) * 2 * np.pi / w)
    d1, d2 = np.abs(growth[1] - growth[0]), np.abs(growth[2] - growth[1])
    assert np.all(d2 < d1 / 8) and d2.max() < 1e-7


def test_the_modal_spectrum_is_that_of_the_projected_samples(crank4):
    """Projecting a spectrum harmonic by harmonic equals transforming the projected samples
    (both are linear in the samples), for every coefficient term and any number of modes."""
    Phi = mean_modes(crank4).shapes
    for k in (3, crank4.n):
        for X, spectrum in zip((crank4.mass, crank4.damping, crank4.stiffness), crank4._power_spectra):
            projected = Phi[:, :k].T @ X @ Phi[:, :k]  # (p, k, k) or (P, p, k, k)
            ref = fourier_coefficients(np.moveaxis(projected, 0, -1) if X.ndim == 4 else projected)
            got = modal_spectrum(spectrum, Phi[:, :k])
            assert got.shape == ref.shape
            assert np.abs(got - ref).max() <= 1e-12 * np.abs(ref).max()
            assert np.array_equal(got[::-1], np.conj(got))  # the spectrum of real samples


def test_the_modal_spectrum_of_a_rectangular_block(crank4):
    """Rows on one set of modes and columns on another (either side the narrower): the
    spectrum of the projected samples, and the block of the square projection (to rounding
    of the whole term: the mass's off-diagonal blocks are rounding only, M-orthonormal modes)."""
    Phi = mean_modes(crank4).shapes
    l, h = Phi[:, :3], Phi[:, 3:]
    for X, spectrum in zip((crank4.mass, crank4.damping, crank4.stiffness), crank4._power_spectra):
        square = modal_spectrum(spectrum, Phi)
        for rows, cols, block in ((h, l, square[:, 3:, :3]), (l, h, square[:, :3, 3:])):
            projected = rows.T @ X @ cols
            ref = fourier_coefficients(np.moveaxis(projected, 0, -1) if X.ndim == 4 else projected)
            got = modal_spectrum(spectrum, rows, cols)
            assert got.shape == ref.shape == block.shape
            scale = np.abs(square).max()
            assert np.abs(got - ref).max() <= 1e-12 * scale and np.abs(got - block).max() <= 1e-12 * scale


def test_the_guard_keeps_underdamped_modes_within_parametric_reach(crank4):
    modes = MeanModes(np.eye(5), np.array([1.0, 2.0, 5.0, 9.0, 30.0]), np.array([0.01, 0.01, 0.02, 2.0, 0.01]), 0.0)
    assert guarded_modes(modes, 1, 2, 1.0) == 2  # 2 - 1 <= 2; 5 - 1 > 2
    assert guarded_modes(modes, 1, 4, 1.0) == 3  # 5 - 1 <= 4
    assert guarded_modes(modes, 1, 8, 1.0) == 3  # 9 is overdamped, 30 out of reach
    assert guarded_modes(modes, 1, 30, 1.0) == 5
    # slider-crank: rod modes 830, 3330, 7600 rad/s; m = 12 at 600 rad/s reaches 830 + 7200
    assert modal_reduction(crank4, 2, harmonics=12, omega_max=300.0).n == 2
    assert modal_reduction(crank4, 2, harmonics=12, omega_max=600.0).n == 3


def test_bad_input_is_refused(crank4):
    for bad in (0, crank4.n + 1, 2.5, True):
        with pytest.raises(InputError, match="modes"):
            modal_reduction(crank4, bad)
    with pytest.raises(InputError, match="both"):
        modal_reduction(crank4, 2, harmonics=12)
