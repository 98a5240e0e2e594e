"""Prescribed motions and loads as functions of the driving angle theta = omega t
(Schwab & Meijaard 2001, eq. 2 and 7: any periodic q^r(t), the F_{,q^r} q''^r term) on
the slider-crank of sec. 4.2, declared in an element file: a crank speed
omega (1 + 0.1 sin theta) (sweeps/slider_crank_varying_speed.toml) and a piston gas-force
table on the plunger. The omega split against direct linearization per speed, harmonic
balance against direct integration of the linearized equations and against the full
non-linear equations; the constant-speed model unchanged through the new path."""

import tomllib

import numpy as np
import pytest

import periodyn
from periodyn.errors import InputError
from periodyn.model.driving import AngleFunction
from periodyn.model.linearization import linearize, omega_split, reduced_residual
from periodyn.nonlinear.elements import element_dae
from periodyn.numerics.spectra import fourier_coefficients
from periodyn.periodic import half_range_and_mean
from periodyn.studies.checks import Checker
from periodyn.studies.elements import check_element_form, declared_model
from periodyn.studies.spec import project_root

FILE = project_root() / "sweeps" / "slider_crank_varying_speed.toml"
GAS_TABLE = 72            # samples of the gas force over one turn (every 5 degrees)
GAS_PEAK = 50.0           # N, pushing the plunger towards the crank, 0.3 rad after top dead centre


def _gas_force() -> list[float]:
    theta = 2 * np.pi * np.arange(GAS_TABLE) / GAS_TABLE
    return (-GAS_PEAK * np.exp(-(np.angle(np.exp(1j * (theta - 0.3))) / 0.35) ** 2)).tolist()


def _model(crank=None, loads=None):
    """The compiled model of the element file, with the crank input and loads replaced."""
    table = dict(tomllib.loads(FILE.read_text())["model"])
    if crank is not None:
        table["prescribed"] = {"crank": crank}
    if loads is not None:
        table["loads"] = loads
    return declared_model(check_element_form(Checker(str(FILE)), table), name="slider_crank").compile()


@pytest.fixture(scope="module")
def models():
    return {"varying speed": _model(), "gas force": _model(1.0, [{"coordinate": "B.x", "samples": _gas_force()}])}


def test_angle_function_forms_agree():
    """theta + 0.1 (1 - cos theta) from coefficients, from 16 samples and from a callable:
    values and derivatives at arbitrary angles; a callable with a wrong derivative is refused."""
    theta = np.linspace(-1.0, 9.0, 23)
    exact = (theta + 0.1 * (1 - np.cos(theta)), 1 + 0.1 * np.sin(theta), 0.1 * np.cos(theta))
    grid = 2 * np.pi * np.arange(16) / 16
    forms = (AngleFunction.fourier([-0.1], mean=0.1, rate=1.0),
             AngleFunction.samples(grid + 0.1 * (1 - np.cos(grid)), rate=1.0),
             AngleFunction.from_callable(lambda t: exact_of(t)))
    for g in forms:
        for got, want in zip(g(theta), exact):
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-14)
    assert forms[2].rate == pytest.approx(1.0, rel=1e-14)
    with pytest.raises(InputError, match="central differences"):
        AngleFunction.from_callable(lambda t: (np.sin(t), np.cos(t), np.cos(t)))
    with pytest.raises(InputError, match="periodic"):
        AngleFunction.from_callable(lambda t: (t * t, 2 * t, 2 + 0 * t))


def exact_of(t):
    return t + 0.1 * (1 - np.cos(t)), 1 + 0.1 * np.sin(t), 0.1 * np.cos(t)


def test_constant_speed_is_unchanged_through_the_function_path():
    """crank = { rate = 1.0 } (g(theta) = theta through the function-of-theta code path:
    per-sample rates, zero input accelerations and loads) equals crank = 1.0 to 1e-12."""
    plain, function = omega_split(_model(1.0), 16), omega_split(_model({"rate": 1.0}), 16)
    assert _model({"rate": 1.0}).input_motions and _model(1.0).uniform
    for name in ("mass", "damping", "stiffness", "force", "output_maps"):
        a, b = np.asarray(getattr(function, name)), np.asarray(getattr(plain, name))
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max())


@pytest.mark.parametrize("case", ["varying speed", "gas force"])
def test_omega_split_equals_direct_linearization(models, case):
    """The omega polynomials at 150 and 260 rad/s against the matrices linearized at that
    speed (rates omega g', accelerations omega^2 g'', loads per sample) to 1e-10; and each
    case differs from the constant-speed model (the terms are there): the stiffness by
    more than 0.5 % in both (measured 1.4 % and 1.2 % at 150 rad/s), the force by more
    than 10 % with the varying speed (16 %; the gas force along the inextensible rod's
    chord moves no dynamic coordinate to first order, so it only compresses the rod)."""
    model = models[case]
    split, constant = omega_split(model, 32), omega_split(_model(1.0), 32)
    for omega in (150.0, 260.0):
        lin, at = linearize(model, omega, 32), split.at(omega)
        for got, want in ((at.mass, lin.mass), (at.damping, lin.damping), (at.stiffness, lin.stiffness),
                          (at.force, lin.force)):
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * np.abs(want).max())
        base = constant.at(omega)
        assert np.abs(lin.stiffness - base.stiffness).max() > 0.005 * np.abs(base.stiffness).max()
        if case == "varying speed":
            assert np.abs(lin.force - base.force).max() > 0.1 * np.abs(base.force).max()


@pytest.mark.parametrize("case", ["varying speed", "gas force"])
def test_nominal_accelerations_and_stiffness_match_the_nonlinear_equations(models, case):
    """Independent of the split kernel: on the rigid motion (q^d = 0) the full non-linear
    equations (dense nodal assembly, :mod:`periodyn.kernels.mechanism.equations`) give
    q''^d = M^-1 f at every sample, and central differences of the residual of eq. (4) in
    q^d (at q'^d = q''^d = 0) give K (eq. 4 against eq. 13)."""
    model, omega, p = models[case], 200.0, 8
    sys = omega_split(model, p).at(omega)
    eq = element_dae(model).equations
    theta = np.arange(p) * 2 * np.pi / p
    nd, h = model.n_dynamic, 1e-5
    acc = eq(np.zeros((p, nd)), np.zeros((p, nd)), theta / omega, omega, False)[0]
    want = np.linalg.solve(sys.mass, sys.force[..., None])[..., 0]
    np.testing.assert_allclose(acc, want, rtol=0, atol=1e-9 * np.abs(want).max())
    zero = np.zeros(nd)
    for j in (1, 3, 6):
        fd = np.column_stack([(reduced_residual(model, theta[j], h * e, zero, zero, omega)
                               - reduced_residual(model, theta[j], -h * e, zero, zero, omega)) / (2 * h)
                              for e in np.eye(nd)])
        np.testing.assert_allclose(fd, sys.stiffness[j], rtol=0, atol=1e-6 * np.abs(sys.stiffness[j]).max())


@pytest.mark.parametrize("case", ["varying speed", "gas force"])
def test_harmonic_balance_agrees_with_direct_integration(models, case):
    """From the harmonic-balance state at t = 0, integrating the linearized periodic
    equations over one period (transient(..., method="integrate")) stays on the harmonic
    balance solution to 1e-8 (24 harmonics, 64 samples; measured 1.3e-11 for the varying speed)."""
    sys = omega_split(models[case], 64).at(150.0)
    sol = periodyn.periodic_solution(sys, 24)
    t = np.linspace(0.0, sys.period, 41)
    y0 = np.concatenate([sol(0.0)[0], sol.velocity(0.0)[0]])
    tr = periodyn.transient(sys, sol, y0, t, method="integrate")
    assert np.abs(tr.q - tr.periodic_q).max() < 1e-8 * np.abs(tr.q).max()


@pytest.mark.slow
def test_harmonic_balance_agrees_with_nonlinear_shooting_within_the_linearization_error(models):
    """The full non-linear equations (4) with the crank speed omega (1 + 0.1 sin theta), solved
    by DOP853 shooting from the linearized harmonic balance at 150 rad/s: the orbits differ by
    less than 3 % of the amplitude (measured 0.97 %, amplitude 0.031 rad: first order in the
    amplitude, the linearization's error) and the midpoint deflection amplitudes by less than
    3 % (measured 0.78 %), the bound the constant-speed model meets
    (tests/validation/test_slider_crank_nonlinear.py; the paper's "within a few percent")."""
    model, omega = models["varying speed"], 150.0
    lin = periodyn.periodic_solution(omega_split(model, 64).at(omega), 16)
    shot = periodyn.shooting(element_dae(model), omega, initial=lin, tol=1e-10, rtol=1e-11)
    t = np.arange(64) * 2 * np.pi / (64 * omega)
    assert shot.residual <= 1e-10
    amplitude = np.abs(lin(t)).max()
    assert np.abs(shot(t) - lin(t)).max() < 0.03 * amplitude
    y = periodyn.element_outputs(model, omega, t, shot(t))[:, 0]
    amp_nl = half_range_and_mean(fourier_coefficients(y[:, None], 31))[0][0]
    assert abs(amp_nl / lin.output_amplitude()[0] - 1) < 0.03
