"""Stability method "reduced": the ladder on a mean-system modal reduction with the
Schur-complement correction, against fine Magnus references of the full models."""

import numpy as np
import pytest

import periodyn
from periodyn import characteristic_exponents
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
from periodyn.kernels.solvers.magnus_ladder import streamed_moduli
from periodyn.model.linearization import omega_split
from periodyn.speeds import SpeedSolver
from periodyn.stability.magnus import MagnusLadder
from periodyn.stability.methods import names
from periodyn.stability.reduced import ReducedStability


def crank(elements: int, damping: float = 0.02):
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=elements))
    return omega_split(slider_crank_model(2 * damping / w1, rod_elements=elements), 64)


def reference(model, w: np.ndarray, steps: int = 4096) -> np.ndarray:
    """log max|mu| (S,) of the full model by order-6 Magnus with ``steps`` steps (the
    references of benchmarks/bench_stability_auto.py --errors, converged to about 1e-11 here)."""
    L = MagnusLadder(*model._power_spectra[:3])
    d, out = 2 * L.n, np.empty(w.size)
    exps, mod, Phi = np.empty(d, complex), np.empty(d), np.empty((d, d))
    for i, omega in enumerate(w):
        streamed_moduli(L._rows, L.n, *L.powers, steps, 3, L.span, L.scale, 64, float(omega), L._signs(), Phi, exps, mod)
        out[i] = np.log(mod[-1])
    return out


def corrected(R: ReducedStability, w: np.ndarray, k: int):
    """Uncorrected and corrected log max|mu| and the bound with k modes at speeds w."""
    est = R.ladder(k).solve(w, np.inf)
    rows = [R.certify(wi, 12, k, e, err) for wi, e, err in zip(w, est.exponents, est.error)]
    return (est.exponents.real.max(axis=1) * 2 * np.pi / w, np.array([r[1] for r in rows]),
            np.array([r[2] for r in rows]))


@pytest.mark.parametrize("elements, k", [(4, 4), (8, 4), (8, 8)])
def test_the_correction_meets_the_full_model(elements, k):
    """Over 150-300 rad/s the truncation error of log max|mu| (up to 5e-5 with 4 of 8
    modes) is corrected to 1e-8, and the bound (ladder error + 2 |d_lambda| T) covers
    both the corrected and the uncorrected error."""
    model = crank(elements)
    w = np.array([150.0, 225.0, 300.0])
    ref = reference(model, w)
    raw, G, bound = corrected(ReducedStability(model), w, k)
    assert np.all(np.abs(G - ref) <= 1e-8)
    assert np.all(bound >= np.abs(G - ref)) and np.all(bound >= np.abs(raw - ref))
    assert np.abs(raw - ref).max() > 10 * np.abs(G - ref).max()


@pytest.fixture(scope="module")
def light():
    """8 rod elements, 0.2 % damping: unstable in a zone near 265.95-267.35 rad/s."""
    return crank(8, 0.002)


ZONE = np.array([265.8, 266.1, 267.2, 267.5])  # both sides of both edges


def test_the_correction_holds_at_the_edges_of_an_instability_zone(light):
    """Near the zone's edges the truncation error is amplified (4.5e-5 with 4 modes); the
    correction with 8 modes meets the reference to 1e-8 and the bound covers it."""
    ref = reference(light, ZONE)
    assert list(ref > 1e-6) == [False, True, True, False]
    R = ReducedStability(light)
    raw, G, bound = corrected(R, ZONE, 4)
    assert np.all(bound >= np.abs(raw - ref)) and np.abs(raw - ref).max() > 1e-5
    raw, G, bound = corrected(R, ZONE, 8)
    assert np.all(np.abs(G - ref) <= 1e-8) and np.all(bound >= np.abs(G - ref))


def test_sweep_verdicts_in_the_zone_equal_the_full_models(light):
    solver = SpeedSolver(light, 12, stability="reduced")
    res = solver.solve_many(ZONE)
    assert list(res.stable) == [True, False, False, True]
    assert set(res.method) <= {"reduced", "auto"}
    G = res.max_real * 2 * np.pi / ZONE
    assert np.all(np.abs(G - reference(light, ZONE)) <= 1e-6 * np.maximum(1, np.abs(G)))


def test_certified_speeds_and_the_scalar_entry():
    """Speeds certified by the sweep's method are within their bound of the reference;
    the scalar entry (the system's own mean modes) gives the same growth."""
    model = crank(8)
    w = np.array([160.0, 230.0])
    ref = reference(model, w)
    exps, done, reasons, records = ReducedStability(model).solve(w, 12)
    assert done.all() and all(r.startswith("reduced: ") for r in reasons)
    bounds = records["stability_error_bound"]
    G = exps.real.max(axis=1) * 2 * np.pi / w
    assert np.all(np.abs(G - ref) <= bounds) and np.all(np.abs(G - ref) <= 1e-8)
    fl = characteristic_exponents(model.at(230.0), 12, "reduced")
    assert "reduced" in names() and fl.method in ("reduced", "auto") and fl.exponents.size == 2 * model.n
    assert abs(fl.max_real * fl.period - ref[1]) <= 1e-6


def test_the_correction_on_the_band_above_noise_equals_the_all_harmonics_one(monkeypatch):
    """The coupling products take the coefficient harmonics up to the highest above the noise
    floors (22 of 31 on the 16-element slider-crank, 47 angles instead of 56): d_lambda agrees
    with the products of every harmonic to 1e-9 of itself (measured 6e-16)."""
    R = ReducedStability(crank(16))
    w, k = np.array([150.0, 210.0, 266.5, 300.0]), 10
    lam = [e[np.argmax(e.real)] for e in R.ladder(k).solve(w, np.inf).exponents]
    banded = np.array([R.correction(x, wi, 12, k)[1] for x, wi in zip(lam, w)])
    K0 = (R.model._power_spectra[0].shape[0] - 1) // 2
    assert {key[2] for key in R._couplings} == {22}
    every = ReducedStability._coupled
    monkeypatch.setattr(R, "_coupled", lambda *a: every(R, *a, band=K0))
    full = np.array([R.correction(x, wi, 12, k)[1] for x, wi in zip(lam, w)])
    assert {key[2] for key in R._couplings} == {22, K0}
    assert np.all(np.abs(banded - full) <= 1e-9 * np.abs(full)) and np.all(np.abs(full) * 2 * np.pi / w > 1e-9)


@pytest.mark.slow
def test_the_correction_meets_the_16_element_model():
    model = crank(16)
    w = np.array([150.0, 200.0, 250.0, 300.0])
    ref = reference(model, w)
    R = ReducedStability(model)
    for k in (4, 8):
        raw, G, bound = corrected(R, w, k)
        assert np.all(np.abs(G - ref) <= 1e-8) and np.all(bound >= np.abs(G - ref))
        assert np.all(bound >= np.abs(raw - ref))


def test_a_sweep_records_the_reduced_method():
    model = crank(8)
    w = np.array([160.0, 230.0])
    ds = periodyn.sweep(model, w, 12, 64, stability="reduced", progress=False)
    assert list(ds["stability_method"].values) == ["reduced", "reduced"]
    assert np.allclose(ds["max_real_exponent"].values * 2 * np.pi / w, reference(model, w), rtol=0, atol=1e-8)


def test_a_sweep_records_modes_correction_and_bound(tmp_path):
    """A "reduced" sweep records k, |d_lambda| and the bound per speed; the bound covers
    the true error of max Re(lambda) T against the full model's reference, the correction
    is the one the reduced model's own certify step finds, and the columns survive
    save/load; a sweep by another method holds the fill values."""
    model = crank(8)
    w = np.array([160.0, 230.0])
    ds = periodyn.sweep(model, w, 12, 64, stability="reduced", progress=False)
    k = ds["reduced_modes"].values
    assert ds["reduced_modes"].dtype.kind == "i" and np.all((k > 0) & (k < model.n))
    err = np.abs(ds["max_real_exponent"].values * 2 * np.pi / w - reference(model, w))
    assert np.all(ds["stability_error_bound"].values >= err)
    R = ReducedStability(model)
    for i, wi in enumerate(w):
        est = R.ladder(int(k[i])).solve(w[i:i + 1], np.inf)
        dl = R.certify(wi, 12, int(k[i]), est.exponents[0], est.error[0])[3]
        assert ds["reduced_correction"].values[i] == pytest.approx(dl * wi / (2 * np.pi), rel=1e-9)
        assert ds["reduced_correction"].values[i] > 0
    assert ds["stability_error_bound"].attrs["units"] == "1" and ds["reduced_correction"].attrs["units"] == "1/s"
    back = periodyn.results.load(periodyn.results.save(ds, tmp_path / "reduced.nc"))
    for name in ("reduced_modes", "reduced_correction", "stability_error_bound"):
        np.testing.assert_array_equal(back[name].values, ds[name].values)
        assert back[name].dtype == ds[name].dtype and back[name].attrs == ds[name].attrs
    other = periodyn.sweep(model, w, 12, 64, stability="auto", progress=False)
    assert np.all(other["reduced_modes"].values == 0)
    assert np.isnan(other["reduced_correction"].values).all() and np.isnan(other["stability_error_bound"].values).all()
