"""Cardan drive shaft, Schwab & Meijaard (2001) section 4.4, eq. (31)-(33), Fig. 9-12:
rigid kinematics and static joint loads against the closed forms, the pinned shaft's
bending frequency (766 rad/s) and the torsion frequency omega_b / sqrt(2), the static
twist, the symmetries of the harmonics, the maximum twist (0.012 rad), the unstable
zones (0.65-0.68 and 0.78-0.92 of omega_b, Neimark-Hopf, checked by the monodromy
matrix) and the resonances near 1/2, 1/3, 1/4 of omega_b."""

import numpy as np
import pytest

import periodyn
from periodyn import TruncationWarning
from periodyn.speeds import SpeedSolver
from periodyn.examples.cardan import CARDAN, cardan_frequencies, cardan_shaft, cardan_shaft_model
from periodyn.examples.cardan_zones import cardan_boundaries
from periodyn.kernels.mechanism import assembly
from periodyn.model.kinematics import motion, nominal_configurations
from periodyn.model.linearization import linearize

ALPHA = np.pi / 6
OMEGA_B = 766.0          # rad/s, the paper's first bending frequency of the pinned shaft
M_O = CARDAN["output_torque"]
GJ = 210e9 / 2.6 * np.pi * 0.03**4 / 2
PAPER_BOUNDARIES = (0.65, 0.68, 0.78, 0.92)  # omega/omega_b, read off Fig. 9-10
EULER_BERNOULLI = np.pi**2 * np.sqrt(210e9 * np.pi * 0.03**4 / 4 / (7850 * np.pi * 0.03**2))   # 765.71 rad/s


@pytest.fixture(scope="module")
def shaft():
    return cardan_shaft(ALPHA)


def _mode_motion(model, mode, p):
    """Angle and rate (per unit input speed) of a hinge rotation mode at p input angles."""
    X = nominal_configurations(model, p)
    arr = model.arrays
    k = model.mode_names.index(mode)
    e = int(np.nonzero(arr.modes[:, 0] == k)[0][0])
    dofs = arr.dofs[e, :arr.ndof[e]]
    tensors = assembly.allocate_tensors(arr)
    angle, rate = np.empty(p), np.empty(p)
    nq = model.n_inputs + model.n_dynamic
    for j in range(p):
        qdot = np.zeros(nq)
        qdot[0] = 1.0
        v = motion(model, X[j], qdot, np.zeros(nq)).v
        assembly.element_tensors(arr, X[j], *tensors)
        angle[j] = tensors[0][e, 0]
        rate[j] = tensors[1][e, 0, :dofs.size] @ v[dofs]
    return angle, rate


def test_rigid_kinematics_drive_shaft_speed_eq31_and_output_equals_input():
    model = cardan_shaft_model(ALPHA)
    p = 36
    theta = 2 * np.pi * np.arange(p) / p
    _, rate = _mode_motion(model, "frame_bearing.rotation", p)
    np.testing.assert_allclose(rate, np.cos(ALPHA) / (1 - np.sin(ALPHA) ** 2 * np.cos(theta) ** 2), atol=1e-10)
    angle, rate = _mode_motion(model, "bearing_out.rotation", p)
    np.testing.assert_allclose(np.unwrap(angle), np.unwrap(theta), atol=1e-10)
    np.testing.assert_allclose(rate, 1.0, atol=1e-10)


def test_static_drive_shaft_torque_eq32_and_bending_moment_eq33():
    """At rest the additional forces on the flexible modes are the stresses that keep the
    rigid mechanism in equilibrium under M_o: the torque of both elements is eq. (32),
    the bending moment about the yoke-normal axis is eq. (33) at every section (a pure
    couple), and the one about the yoke pins vanishes."""
    model = cardan_shaft_model(ALPHA)
    p = 24
    theta = 2 * np.pi * np.arange(p) / p
    fd = linearize(model, 0.0, p).additional_force
    col = {name: fd[:, i] for i, name in enumerate(model.dynamic_names)}
    c2 = np.sin(ALPHA) ** 2 * np.cos(theta) ** 2
    torque = (1 - c2) / np.cos(ALPHA) * M_O
    moment = np.tan(ALPHA) * np.cos(theta) * np.sqrt(1 - c2) * M_O
    for e in ("beam1", "beam2"):
        np.testing.assert_allclose(col[f"{e}.torsion"], torque, rtol=1e-8)
        np.testing.assert_allclose(col[f"{e}.bending_y_p"], moment, atol=1e-8 * M_O)
        np.testing.assert_allclose(col[f"{e}.bending_y_q"], -moment, atol=1e-8 * M_O)
        for mode in ("bending_z_p", "bending_z_q"):
            np.testing.assert_allclose(col[f"{e}.{mode}"], 0.0, atol=1e-8 * M_O)


def test_bending_frequency_of_the_pinned_shaft():
    """omega_b of the undamped shaft between the joints at rest: two elements with lumped
    rotary inertia (the paper's model) 767.9 rad/s, 0.25 % above the paper's 766; refined
    without rotary inertia it converges to the Euler-Bernoulli 765.71 that 766 rounds."""
    two = cardan_frequencies(cardan_shaft_model(0.0, output_torque=0.0))["bending"]
    assert two == pytest.approx(767.87, abs=0.01)
    assert abs(two / OMEGA_B - 1) < 3e-3
    refined = cardan_frequencies(cardan_shaft_model(0.0, output_torque=0.0, elements=16, rotary_inertia=False))
    assert refined["bending"] == pytest.approx(EULER_BERNOULLI, rel=2e-6)
    assert EULER_BERNOULLI == pytest.approx(OMEGA_B, abs=0.5)


def test_torsion_frequency_at_zero_misalignment():
    """Two elements, lumped rotary inertia: the twist of the input end is held by joint 1,
    the middle node carries rhoJ L / 2, the far end rhoJ L / 4 + I_o, each element GJ / (L/2):
    the two-mass closed form to round-off, and omega_b / sqrt(2) to 0.2 %."""
    omega = cardan_frequencies(cardan_shaft_model(0.0, output_torque=0.0))
    rho_j = 7850 * np.pi * 0.03**4 / 2
    M = np.diag([rho_j / 2, rho_j / 4 + CARDAN["output_inertia"]])
    K = 2 * GJ / CARDAN["length"] * np.array([[2.0, -1.0], [-1.0, 1.0]])
    closed = np.sqrt(np.min(np.linalg.eigvals(np.linalg.solve(M, K)).real))
    assert omega["torsion"] == pytest.approx(closed, rel=1e-9)
    assert omega["torsion"] == pytest.approx(omega["bending"] / np.sqrt(2), rel=2e-3)
    assert omega["torsion"] == pytest.approx(OMEGA_B / np.sqrt(2), rel=2e-3)


def test_static_twist_without_misalignment():
    system = cardan_shaft(0.0, samples=16).at(1.0)
    sol = periodyn.periodic_solution(system, 4)
    twist = sol.output_mean()[system.output_names.index("twist")]
    assert twist == pytest.approx(M_O * CARDAN["length"] / GJ, rel=1e-8)
    assert np.abs(sol.output_amplitude()).max() < 1e-12


@pytest.mark.parametrize("ratio", [0.1, 0.34, 0.5, 0.85])
def test_harmonics_symmetry(shaft, ratio):
    """Even harmonics of the deflections and odd harmonics of the twist vanish."""
    sol = periodyn.periodic_solution(shaft.at(ratio * OMEGA_B), 12)
    H = np.abs(sol.output_harmonics)[12:]     # l = 0..m
    names = shaft.output_names
    for name in ("midpoint_deflection", "midpoint_deflection_normal"):
        h = H[:, names.index(name)]
        assert h[0::2].max() < 1e-12 * h.max()
    h = H[:, names.index("twist")]
    assert h[1::2].max() < 1e-12 * h.max()


def _max_twist(system):
    sol = periodyn.periodic_solution(system, 12)
    t = np.linspace(0, sol.period, 721)
    return sol.outputs(t)[:, system.output_names.index("twist")].max()


def test_maximum_twist_at_the_ends_of_the_range(shaft):
    """0.012 rad at both ends of the range, about 20 % above the static twist at zero
    misalignment (the paper's Fig. 10)."""
    static = M_O * CARDAN["length"] / GJ
    for ratio in (0.02, 0.999):
        peak = _max_twist(shaft.at(ratio * OMEGA_B))
        assert peak == pytest.approx(0.012, abs=5e-4)
        assert 1.12 < peak / static < 1.25


def _assert_paper_zones(wb, checks):
    """Four boundaries near the paper's, zone 1 by a real multiplier through +1, zone 2 by
    a complex pair, each confirmed by the monodromy matrix to either side."""
    ratios = [c.boundary.omega / wb for c in checks]
    assert len(checks) == 4, ratios
    np.testing.assert_allclose(ratios, PAPER_BOUNDARIES, atol=0.012)
    assert [c.boundary.becomes_stable for c in checks] == [False, True, False, True]
    assert [c.boundary.kind for c in checks] == ["fold", "fold", "neimark-sacker", "neimark-sacker"]
    assert all(c.agrees for c in checks), checks


@pytest.mark.slow
def test_unstable_zones_typed_and_checked_by_monodromy():
    """Zones 0.65-0.68 and 0.78-0.92 of omega_b (the paper's Fig. 9-10, read off the
    figure); boundaries by bisection (m = 12, 64 samples, the sweep file's), typed from
    the critical multiplier and checked just inside and outside each boundary by the
    monodromy matrix (DOP853), :func:`periodyn.examples.cardan_zones.cardan_boundaries`.

    The paper calls all four boundaries Neimark-Hopf (a complex pair of exponents crossing
    the imaginary axis). The multipliers say otherwise for the first zone: there a complex
    pair of multipliers meets on the positive real axis and one real multiplier leaves the
    unit circle through +1 (exponents sigma +- i omega: complex conjugate exponents, as the
    paper says, but a real multiplier), a combination resonance; only the second zone is a
    Neimark-Sacker (complex multiplier pair at angle ~ +-1.4 rad) crossing."""
    wb, checks = cardan_boundaries()
    _assert_paper_zones(wb, checks)


def test_unstable_zones_reduced_typed_and_checked_by_monodromy():
    """The same four boundaries on a reduced case (m = 6, 32 samples, one grid point
    inside each zone and on either side, coarser bisection): the paper's zones and the
    same types, each confirmed by the monodromy matrix of the reduced model. At m = 6 Hill's
    edge energy reaches 1.2e-6 on a boundary, above the truncation tolerance: accepted with a
    TruncationWarning, the monodromy check being the independent judge here."""
    with pytest.warns(TruncationWarning):
        wb, checks = cardan_boundaries(harmonics=6, samples=32, grid=[0.62, 0.665, 0.72, 0.85, 0.95], xtol=1e-6,
                                       truncation="warn")
    _assert_paper_zones(wb, checks)


def test_unstable_inside_the_zones_and_stable_between(shaft):
    for ratio, stable in ((0.62, True), (0.665, False), (0.72, True), (0.85, False), (0.95, True)):
        system = shaft.at(ratio * OMEGA_B)
        assert periodyn.characteristic_exponents(system, 12, method="dense").stable is stable, ratio
        assert periodyn.characteristic_exponents(system, 12, method="monodromy").stable is stable, ratio


def test_default_stability_method_gives_dense_hill_verdicts(shaft):
    """The sweep file's default ("auto"): the half-period Magnus ladder from 0.01 omega_b on,
    dense Hill at the lowest speed; the same verdicts and max Re(lambda) as dense Hill where
    m = 12 resolves Hill's exponents. Below 0.01 omega_b a period spans hundreds of bending
    periods and the stiff modes' eigenvectors reach the outermost harmonics (edge energy
    9e-3 at 0.01, 7.5e-2 at 0.002 omega_b): dense Hill's points are failed, with the reason."""
    ratio = np.array([0.002, 0.01, 0.1, 0.3, 0.5, 0.62, 0.665, 0.72, 0.85, 0.95, 0.999])
    with pytest.warns(TruncationWarning):
        auto = SpeedSolver(shaft, 12).solve_many(ratio * OMEGA_B)
    with pytest.warns(TruncationWarning):
        dense = SpeedSolver(shaft, 12, stability="dense").solve_many(ratio * OMEGA_B)
    assert list(auto.method) == ["dense"] + ["magnus"] * 10
    resolved = dense.message == ""
    assert list(resolved) == [False, False] + [True] * 9 and auto.message[0] == dense.message[0]
    assert all("truncated" in m and "increase harmonics" in m for m in dense.message[:2])
    np.testing.assert_array_equal(auto.stable[resolved], dense.stable[resolved])
    np.testing.assert_array_equal(auto.stable, [False] + [True] * 5 + [False, True, False, True, True])
    period = 2 * np.pi / (ratio * OMEGA_B)   # Magnus certifies log max|mu| to 1e-6 max(1, |log max|mu||)
    growth = np.abs(dense.max_real) * period
    assert (np.abs(auto.max_real - dense.max_real) * period <= 1e-6 * np.maximum(1.0, growth))[resolved].all()


def _peaks(omega, amp):
    inner = (amp[1:-1] > amp[:-2]) & (amp[1:-1] > amp[2:])
    return omega[1:-1][inner]


@pytest.mark.slow
def test_resonances_near_half_third_quarter_with_split_peaks(shaft):
    """Deflection peaks near omega_b / 4, / 3 and / 2; two peaks close together at 1/2 and 1/4
    (the two bending modes split by torque and misalignment): the pairs at 1/2 and 1/4
    belong to the same two frequencies (2 x the 1/2 peaks = 4 x the 1/4 peaks)."""
    windows = {4: (0.235, 0.27), 3: (0.32, 0.35), 2: (0.47, 0.54)}
    peaks = {}
    for k, (lo, hi) in windows.items():
        ratio = np.arange(lo, hi, 0.0005)
        data = periodyn.sweep(shaft, ratio * OMEGA_B, 12, stability=False, progress=False)
        peaks[k] = _peaks(ratio, data["amplitude"].sel(output="midpoint_deflection").values)
    assert len(peaks[4]) == 2 and len(peaks[2]) == 2 and len(peaks[3]) >= 1, peaks
    np.testing.assert_allclose(2 * peaks[2], 4 * peaks[4], rtol=0.02)   # frequencies shift with speed
    assert abs(peaks[2][0] - 0.5) < 0.01 and abs(peaks[4][0] - 0.25) < 0.005


def test_bad_input_is_refused_with_the_fix():
    from periodyn.errors import InputError
    with pytest.raises(InputError, match="alpha"):
        cardan_shaft(alpha=2.0)
    with pytest.raises(InputError, match="even integer"):
        cardan_shaft(elements=3)
    with pytest.raises(InputError, match="fraction of critical"):
        cardan_shaft(damping=1.5)
    with pytest.raises(InputError, match="alpha"):
        cardan_shaft_model(alpha=-0.1)
