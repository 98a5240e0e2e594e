"""Rotor elements and equations: textbook element matrices, rigid-body gyroscopic
precession, frame equivalence, the periodic co-rotating system of an anisotropic rotor
against the stationary-frame eigenvalues, and clear errors for bad input."""

import numpy as np
import pytest

from periodyn import characteristic_exponents
from periodyn.errors import InputError
from periodyn.results import load, save
from periodyn.rotor import Bearing, Rotor, Seal, campbell, shaft_element

E, RHO, D, LEN = 2.1e11, 7800.0, 0.05, 0.4
A, I = np.pi * D**2 / 4, np.pi * D**4 / 64


def test_shaft_element_matches_the_closed_form_matrices():
    """x-y plane (y1, rz1, y2, rz2): cubic Hermite consistent mass, rotary inertia and
    stiffness as tabulated (e.g. Przemieniecki; Nelson & McVaugh 1976)."""
    L = LEN
    M, G, K = shaft_element(L, E, RHO, D)
    yz = [0, 3, 4, 7]
    trans = RHO * A * L / 420 * np.array([[156, 22 * L, 54, -13 * L], [22 * L, 4 * L**2, 13 * L, -3 * L**2],
                                          [54, 13 * L, 156, -22 * L], [-13 * L, -3 * L**2, -22 * L, 4 * L**2]])
    rot = RHO * I / (30 * L) * np.array([[36, 3 * L, -36, 3 * L], [3 * L, 4 * L**2, -3 * L, -L**2],
                                         [-36, -3 * L, 36, -3 * L], [3 * L, -L**2, -3 * L, 4 * L**2]])
    stiff = E * I / L**3 * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L**2, -6 * L, 2 * L**2],
                                     [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L**2, -6 * L, 4 * L**2]])
    np.testing.assert_allclose(M[np.ix_(yz, yz)], trans + rot, rtol=1e-13, atol=1e-13 * np.abs(trans).max())
    np.testing.assert_allclose(K[np.ix_(yz, yz)], stiff, rtol=1e-13, atol=1e-13 * np.abs(stiff).max())
    # the x-z plane is the same with ry = -dz/dx; the planes do not couple except by G
    sign = np.diag([1.0, -1.0, 1.0, -1.0])
    zy = [1, 2, 5, 6]
    np.testing.assert_allclose(sign @ M[np.ix_(zy, zy)] @ sign, M[np.ix_(yz, yz)], rtol=1e-13)
    assert np.abs(M[np.ix_(yz, zy)]).max() == 0.0 and np.abs(K[np.ix_(yz, zy)]).max() == 0.0
    np.testing.assert_allclose(G, -G.T, atol=0.0)
    # polar inertia 2 rho I: G couples the planes with twice the rotary-inertia matrix
    np.testing.assert_allclose(np.abs(G[np.ix_(zy, yz)]), 2 * np.abs(rot), rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("with_disk", [False, True])
def test_free_spinning_shaft_precesses_at_polar_over_diametral_inertia(with_disk):
    """A free rigid body spinning at Omega tilts in forward precession at
    Omega J_p / J_d (J_d about the centre of mass). The flexible shaft approaches it as
    its stiffness grows (error ~ (precession / bending frequency)^2 ~ 1/E). Its other
    rigid motions (two translations, the static tilt: six zero eigenvalues, which
    rounding scatters to +-1e-8 |lambda|_max in either direction) are three modes of
    frequency exactly 0, whatever the rounding: the same listing when E changes by 1e-12."""
    Jp, Jd = 2 * RHO * I * LEN, RHO * A * LEN**3 / 12 + RHO * I * LEN
    if with_disk:
        Jp, Jd = Jp + 0.02, Jd + 0.011
    speed = 300.0
    precession = speed * Jp / Jd
    errors = []
    for stiffening in (1.0, 100.0, 100.0 * (1 + 1e-12)):
        r = Rotor("free")
        r.add_shaft(0.0, LEN, outer_diameter=D, E=E * stiffening, density=RHO, elements=2)
        if with_disk:
            r.add_disk(LEN / 2, 3.0, 0.02, 0.011)
        ds = campbell(r.compile(), [speed], frame="stationary")
        freq = ds.frequency.values[0]
        rigid = ds.eigenvalue.values[0] == 0.0
        assert rigid.sum() == 3 and np.all(freq[:3] == 0.0) and np.all(np.isnan(ds.damping_ratio.values[0, :3]))
        assert freq[3] == pytest.approx(precession, rel=1e-3) and ds.whirl.values[0, 3] == "forward"
        assert freq[4] > 50 * precession                   # the first bending mode
        errors.append(abs(freq[3] - precession) / precession)
    assert errors[1] < 2e-6
    assert errors[1] < errors[0] / 20 or errors[0] < 1e-6


def _anisotropic(elements=4):
    r = Rotor("aniso")
    r.add_shaft(0.0, LEN, outer_diameter=D, E=E, density=RHO, elements=elements)
    r.add_bearing(Bearing(0.0, kyy=2e7, kzz=5e6, kyz=1e6, kzy=-3e5, cyy=800.0, czz=400.0))
    r.add_bearing(Bearing(LEN, kyy=2e7, kzz=5e6, cyy=800.0, czz=400.0))
    r.add_disk(0.2, 8.0, 0.05, 0.03)
    return r.compile()


def test_anisotropic_rotor_needs_the_stationary_frame():
    model = _anisotropic()
    assert not model.isotropic
    with pytest.raises(InputError, match="depend on the spin angle"):
        campbell(model, [100.0], frame="rotating")
    assert campbell(model, [100.0]).attrs["frame"] == "stationary"


def test_anisotropic_rotor_periodic_corotating_system_matches_stationary_eigenvalues():
    """Co-rotating, anisotropic bearings give periodic coefficients; the Hill exponents
    (defined modulo i Omega) have the real parts of the stationary-frame eigenvalues."""
    model = _anisotropic(elements=2)
    speed = 150.0
    M, C, K = model.equations("stationary").at(speed)
    n = M.shape[0]
    state = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    expected = np.sort(np.linalg.eigvals(state).real)
    floquet = characteristic_exponents(model.rheo_linear(speed, 32), 6, method="dense").exponents
    np.testing.assert_allclose(np.sort(floquet.real), expected, rtol=1e-8, atol=1e-8 * np.abs(expected).max())


def test_isotropic_rotor_is_time_invariant_in_both_frames():
    r = Rotor("iso")
    r.add_shaft(0.0, LEN, outer_diameter=D, E=E, density=RHO, elements=4)
    for at in (0.0, LEN):
        r.add_bearing(Seal(at, K=1e7, k=2e6, C=900.0, c=50.0))
    r.add_disk(0.2, 8.0, 0.05, 0.03)
    model = r.compile()
    speeds = np.linspace(0.0, 2000.0, 7)
    a, b = campbell(model, speeds, frame="rotating"), campbell(model, speeds, frame="stationary")
    np.testing.assert_allclose(a.eigenvalue.values, b.eigenvalue.values, rtol=1e-9, atol=1e-9)
    assert (a.whirl.values == b.whirl.values).all()
    lin = model.rheo_linear(700.0, 8)   # the co-rotating samples do not vary with the angle
    assert np.abs(lin.stiffness - lin.stiffness[0]).max() <= 1e-12 * np.abs(lin.stiffness).max()


def test_campbell_dataset_saves_and_loads(tmp_path):
    ds = campbell(_anisotropic(), np.linspace(0, 500, 5), modes=4)
    back = load(save(ds, tmp_path / "campbell.nc"))
    np.testing.assert_array_equal(back.eigenvalue.values, ds.eigenvalue.values)
    assert (back.whirl.values == ds.whirl.values).all()
    assert back.attrs["frame"] == "stationary"


def test_bad_rotor_input_is_named():
    r = Rotor("bad")
    r.add_shaft(0.0, 1.0, outer_diameter=D, E=E, density=RHO, elements=2)
    r.add_bearing(Bearing(0.3, kyy=1e6, kzz=1e6))
    with pytest.raises(InputError, match=r"bearing at 0.3 m is not on a station; stations are at \[0.0, 0.5, 1.0\]"):
        r.compile()
    massless = Rotor("massless")
    massless.add_shaft(0.0, 1.0, outer_diameter=D, E=E, density=0.0, elements=2)
    massless.add_disk(1.0, 5.0, 0.1, 0.05)
    with pytest.raises(InputError, match=r"mass matrix is singular; coordinates \['s0.y'"):
        massless.compile()
    with pytest.raises(InputError, match="must join end to end"):
        gap = Rotor("gap")
        gap.add_shaft(0.0, 1.0, outer_diameter=D, E=E, density=RHO)
        gap.add_shaft(1.1, 2.0, outer_diameter=D, E=E, density=RHO)
        gap.compile()
    with pytest.raises(InputError, match="end must lie beyond start"):
        Rotor().add_shaft(1.0, 1.0, outer_diameter=D, E=E, density=RHO)
    model = _anisotropic()
    with pytest.raises(InputError, match="speeds must be"):
        campbell(model, [-1.0])
    with pytest.raises(InputError, match="modes must be between"):
        campbell(model, [1.0], modes=0)
    with pytest.raises(InputError, match="compiled rotor"):
        campbell(r, [1.0])


def test_subset_solver_matches_dense():
    from periodyn.examples import rotor

    model = rotor(20)
    speeds = np.linspace(0.0, 900.0, 4)
    dense = campbell(model, speeds, modes=8, eigensolver="dense")
    subset = campbell(model, speeds, modes=8, eigensolver="subset")
    assert subset.attrs["frame"] == "stationary" and dense.attrs["frame"] == "rotating"
    np.testing.assert_allclose(subset.eigenvalue.values, dense.eigenvalue.values, rtol=1e-8)
    assert (subset.whirl.values == dense.whirl.values).all()


def test_stability_threshold_interpolates_the_first_crossing():
    import xarray as xr

    from periodyn.rotor import stability_threshold

    growth = np.array([[-3.0, -1.0], [-2.0, -0.5], [-1.0, 0.5], [1.0, 2.0]])
    ds = xr.Dataset({"eigenvalue": (("speed", "mode"), growth + 100j)}, coords={"speed": [0.0, 10.0, 20.0, 30.0]})
    assert stability_threshold(ds) == pytest.approx(15.0)
    assert np.isnan(stability_threshold(ds.isel(speed=[0, 1])))


def test_rotor_file_is_the_example_rotor(tmp_path):
    from periodyn.studies.spec import project_root
    from periodyn.examples import rotor
    from periodyn.rotor import load_rotor

    path = project_root() / "sweeps" / "rotors" / "table1.toml"
    for elements in (1, 4):
        a = campbell(load_rotor(path, elements=elements), [418.9], modes=8).eigenvalue.values
        b = campbell(rotor(5 * elements), [418.9], modes=8).eigenvalue.values
        np.testing.assert_allclose(a, b, rtol=1e-12)
    bad = tmp_path / "bad.toml"
    bad.write_text(path.read_text().replace("kyy = 1.0e5\nkzz = 1.0e5\n\n[[bearing]]", "kyy = 1.0e5\nkzz = 1.0e5\nkxx = 1.0\n\n[[bearing]]"))
    with pytest.raises(InputError, match=r"\[\[bearing\]\] number 1 has unknown keys \['kxx'\]"):
        load_rotor(bad)


def _jeffcott(beta, ce=20.0):
    """Nearly a Jeffcott rotor: light shaft on stiff end bearings, a 10 kg disk in the
    middle with a stationary damper ce there; internal damping beta (s) in the shaft."""
    length, d = 0.6, 0.02
    r = Rotor("jeffcott")
    r.add_shaft(0.0, length, outer_diameter=d, E=E, density=7.8, elements=2, kelvin_voigt=beta)
    for at in (0.0, length):
        r.add_bearing(Bearing(at, kyy=1e11, kzz=1e11))
    r.add_disk(length / 2, 10.0, 1e-5, 1e-5)
    r.add_bearing(Bearing(length / 2, kyy=0.0, kzz=0.0, cyy=ce, czz=ce))
    k = 48 * E * (np.pi * d**4 / 64) / length**3     # stiffness of the shaft at its middle
    return r.compile(), k, 10.0


def test_internal_damping_is_plain_damping_in_the_rotating_frame():
    """Kelvin-Voigt damping acts on co-rotating strain rates: seen from the rotating
    frame it adds beta K to the damping and nothing to the stiffness."""
    with_damping, _, _ = _jeffcott(2e-4)
    without, _, _ = _jeffcott(0.0)
    a, b = with_damping.equations("rotating"), without.equations("rotating")
    for ka, kb in zip(a.stiffness, b.stiffness):
        np.testing.assert_allclose(ka, kb, rtol=0.0, atol=1e-12 * np.abs(b.stiffness[0]).max())
    shaft = np.zeros_like(b.stiffness[0])
    for el, idx in without.independent:
        if el.name.startswith("shaft"):
            shaft[np.ix_(idx, idx)] += el.stiffness[0]
    np.testing.assert_allclose(a.damping[0] - b.damping[0], 2e-4 * shaft, rtol=1e-12, atol=1e-12 * np.abs(shaft).max())


def test_internal_damping_threshold_is_the_jeffcott_speed():
    """Jeffcott rotor: forward whirl turns unstable at omega_n (1 + c_e / c_i), with
    c_i = beta k (e.g. Genta, Dynamics of Rotating Systems, 2005, sec. 6.4)."""
    beta, ce = 2e-4, 20.0
    model, k, m = _jeffcott(beta, ce)
    wn = np.sqrt(k / m)
    expected = wn * (1.0 + ce / (beta * k))
    ds = campbell(model, np.linspace(0.0, 3.0 * wn, 601), modes=4)
    assert ds.attrs["threshold_speed"] == pytest.approx(expected, rel=1e-3)
    above = campbell(model, [1.05 * expected])
    unstable = above.eigenvalue.values[0].real > 0
    assert unstable.sum() == 1 and above.whirl.values[0][unstable][0] == "forward"


def test_spring_between_stations_acts_on_their_relative_displacement():
    """A lateral spring k between two stations adds [[k, -k], [-k, k]] to their y and
    z stiffness and nothing else; a spring to the same or a missing station is refused."""
    r = Rotor("coupled")
    r.add_shaft(0.0, 0.2, outer_diameter=D, E=E, density=RHO, elements=1)
    r.add_shaft(0.2, 0.4, outer_diameter=D, E=E, density=RHO, elements=1)
    for at in (0.0, 0.4):
        r.add_bearing(Bearing(at, kyy=1e6, kzz=1e6))
    r.add_bearing(Bearing(0.2, kyy=3e5, kzz=3e5, cyy=10.0, czz=10.0, to=0.4))
    model = r.compile()
    plain = Rotor("plain")
    plain.add_shaft(0.0, 0.2, outer_diameter=D, E=E, density=RHO, elements=1)
    plain.add_shaft(0.2, 0.4, outer_diameter=D, E=E, density=RHO, elements=1)
    for at in (0.0, 0.4):
        plain.add_bearing(Bearing(at, kyy=1e6, kzz=1e6))
    K = model.equations("stationary").stiffness[0] - plain.compile().equations("stationary").stiffness[0]
    mid, end = model.coordinate_names.index("s1.y"), model.coordinate_names.index("s2.y")
    expected = np.zeros_like(K)
    for a, sa in ((mid, 1.0), (end, -1.0)):
        for b, sb in ((mid, 1.0), (end, -1.0)):
            expected[a, b] = expected[a + 1, b + 1] = sa * sb * 3e5
    np.testing.assert_allclose(K, expected, atol=1e-6)
    with pytest.raises(InputError, match="'to' must be another station"):
        Bearing(0.2, kyy=1.0, kzz=1.0, to=0.2)
    with pytest.raises(InputError, match=r"bearing end 'to' at 0.3 m is not on a station"):
        bad = Rotor("bad")
        bad.add_shaft(0.0, 0.4, outer_diameter=D, E=E, density=RHO, elements=2)
        bad.add_bearing(Bearing(0.2, kyy=1.0, kzz=1.0, to=0.3))
        bad.compile()
