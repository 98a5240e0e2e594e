"""What the studies store so that figure scripts only read: a continuation study's
``time_history`` (:mod:`periodyn.studies.orbits`; parsed in the one dialect, its
integrated motion checked against the harmonic-balance orbit it starts on), the element
outputs along every orbit (checked against the coordinate they measure) and a sweep's
``quasistatic`` reference (checked against the sampled coefficients)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from periodyn.arclength import Branch
from periodyn.errors import InputError
from periodyn.studies import cache
from periodyn.studies.spec import parse_sweep

ROD = """
[model]
example = "rod_pendulum"
[continuation]
omega = {{ start = 2.5, stop = 5.0, unit = "rad/s" }}
harmonics = 10
{extra}
"""


def _parse(extra: str):
    return parse_sweep(ROD.format(extra=extra), "rod.toml", "rod")


def test_the_time_history_table_is_checked_in_the_one_dialect():
    spec = _parse('time_history = { omega = 3.6, start = "steady_state", samples = 30 }')
    assert spec.time_history == {"omega": 3.6, "branch": "frequency", "start": "steady_state", "samples": 30,
                                 "rtol": 1e-10, "atol": 1e-12}
    for bad, message in (('time_history = { omega = 3.6, start = "rest" }', "unknown start 'rest'"),
                         ('time_history = { omega = 3.6, branch = "period_doubled" }', "needs period_doubling"),
                         ("time_history = { omeg = 3.6 }", "did you mean 'omega'"),
                         ("time_history = { omega = -1.0 }", "must be positive"),
                         ("output_samples = 1", "integer >= 2")):
        with pytest.raises(InputError, match=message):
            _parse(bad)


def test_output_samples_need_an_element_model_with_outputs_before_anything_runs(tmp_path):
    from periodyn.studies.spec import run

    with pytest.raises(InputError, match="rod_pendulum is not an element model with outputs; drop output_samples"):
        run(_parse("output_samples = 16"), tmp_path / "rod.nc")
    assert not (tmp_path / "rod.nc").exists()


def test_the_old_key_reads_as_the_table_and_a_change_makes_the_result_stale():
    with pytest.warns(DeprecationWarning, match="time_history = { omega = w }"):
        old = _parse("time_history_omega = 3.6")
    new = _parse("time_history = { omega = 3.6 }")
    assert old.time_history == new.time_history
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        other = _parse("time_history = { omega = 3.7 }")
    assert cache.fingerprint(new) != cache.fingerprint(other) != cache.fingerprint(_parse(""))


def test_the_integrated_motion_stays_on_the_orbit_it_starts_from():
    """Direct integration (DOP853) from the EGA-IHB orbit's state at t = 0 follows the
    orbit over one period: an independent check of the stored orbit and motion."""
    from periodyn.examples import rod_pendulum
    from periodyn.nonlinear import ihb
    from periodyn.studies.orbits import orbit_time_history

    system = rod_pendulum()
    orbit = ihb(system, 3.6, 10, stability=None)
    branch = Branch.from_solutions([orbit], [orbit.omega], None, (), "one point")
    request = {"omega": 3.6, "branch": "frequency", "start": "orbit", "samples": 12, "rtol": 1e-10, "atol": 1e-12}
    th = orbit_time_history(system, {"frequency": branch}, request, 3.6, 10)
    assert th.sizes == {"time": 12, "orbit_time": 401, "coordinate": 3, "constraint": 2}
    assert th["time"].values[-1] == pytest.approx(2 * np.pi / 3.6, rel=1e-14) and th["time"].attrs["units"] == "s"
    scale = np.abs(th["orbit_q"].values).max(axis=0)
    assert np.all(np.abs(th["q"].values - orbit(th["time"].values)).max(axis=0) < 1e-5 * scale + 1e-9)
    assert np.abs(th["lambda"].values - orbit.lam(th["time"].values)).max() < 1e-4 * np.abs(th["orbit_lambda"]).max()
    assert th.attrs["deviation"] < 1e-5 and th.attrs["orbit_residual"] == orbit.residual
    with pytest.raises(InputError, match="no period_doubled branch"):
        orbit_time_history(system, {"frequency": branch}, {**request, "branch": "period_doubled"}, 3.6, 10)


def test_element_outputs_along_each_orbit_measure_what_they_name():
    """A coordinate output of the pendulum's angle node, measured from the rigid motion,
    is the dynamic coordinate itself at every stored sample (through the non-linear
    kinematics, not the orbit's own harmonics)."""
    from periodyn.examples.elliptic_pendulum import elliptic_pendulum_builder
    from periodyn.nonlinear import element_dae, ihb
    from periodyn.studies.orbits import branch_outputs, element_model_of

    builder = elliptic_pendulum_builder()
    builder.add_coordinate_output("swing", "pendulum", 0.5)
    system = element_dae(builder.compile())
    model = element_model_of(system)
    orbits = [ihb(system, w, 6, stability=None) for w in (1.5, 2.0)]
    branch = Branch.from_solutions(orbits, [o.omega for o in orbits], None, (), "two points")
    ds = branch_outputs(model, branch, 16)
    assert ds["outputs"].shape == (2, 16, 1) and list(ds["output"].values) == ["swing"]
    assert ds["outputs"].attrs["samples_per_period"] == 16
    for k, orbit in enumerate(orbits):
        t = np.arange(16) * orbit.period / 16
        np.testing.assert_allclose(ds["outputs"].values[k, :, 0], orbit(t)[:, 0] / 0.5, rtol=0,
                                   atol=1e-10 * np.abs(orbit(t)).max())
    from periodyn.examples import rod_pendulum

    assert element_model_of(rod_pendulum()) is None


def test_the_quasistatic_reference_is_the_mean_stiffness_solution_of_each_forcing_harmonic(tmp_path):
    """2 |G_0 K_0^-1 f_k| from the sampled coefficients (means over the samples and a
    direct discrete Fourier sum of the force), at every speed."""
    from periodyn.studies.spec import run

    text = ('[model]\nexample = "pendulum"\n[sweep]\nomega = { values = [0.5, 0.8], unit = "omega0" }\n'
            'harmonics = 4\nsamples = 16\nstability = false\nquasistatic = 2\n')
    spec = parse_sweep(text, "q.toml", "q")
    ds = run(spec, tmp_path / "q.nc", workers=1)
    assert ds["quasistatic_amplitude"].dims == ("omega", "quasistatic_harmonic", "output")
    model = spec.build()
    scale = float(ds["quasistatic_amplitude"].max())
    assert scale > 0
    for j, omega in enumerate(ds["omega"].values):
        system = model.at(float(omega))
        theta = 2 * np.pi * np.arange(system.samples) / system.samples
        K0, G0 = system.stiffness.mean(axis=0), system.output_maps.mean(axis=0)
        for k in (1, 2):
            f_k = (system.force * np.exp(-1j * k * theta)[:, None]).mean(axis=0)
            expected = 2 * np.abs(G0 @ np.linalg.solve(K0, f_k))
            np.testing.assert_allclose(ds["quasistatic_amplitude"].values[j, k - 1], expected, rtol=1e-12,
                                       atol=1e-12 * scale)
    with pytest.raises(InputError, match="exceed the sweep's 4"):
        parse_sweep(text.replace("quasistatic = 2", "quasistatic = 5"), "q.toml", "q")
