"""Inputs that used to give wrong answers with exit code 0: each is now refused with a
message naming the file, the table and the fix, or turned into a failed point."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

from periodyn.cli import main
from periodyn.studies.spec import load_sweep_file, parse_sweep
from periodyn.errors import InputError
from periodyn.examples import pendulum
from periodyn.results import STATUS_FAILED, load
from periodyn.engine.front import sweep

W0 = np.sqrt(9.81)

SWEEP = """
[model]
example = "pendulum"
{parameters}
[sweep]
omega = {{ start = 0.944, stop = 1.0, num = 2, unit = "omega0" }}
harmonics = {harmonics}
{samples}
"""


def sweep_text(harmonics=4, parameters="", samples="samples = 24"):
    return SWEEP.format(harmonics=harmonics, parameters=parameters, samples=samples)


def test_zero_harmonics_in_a_sweep_file_is_refused_naming_file_and_table():
    # m = 0 gave amplitude 0 and "stable" at 0.944 and 1.0 omega0, inside the unstable band
    with pytest.raises(InputError, match=r"pend\.toml: \[sweep\] harmonics: .*>= 1"):
        parse_sweep(sweep_text(harmonics=0), "pend.toml")


def test_zero_harmonics_in_sweep_is_refused():
    with pytest.raises(InputError, match="harmonics must be an integer >= 1"):
        sweep(pendulum(samples=24), W0 * np.array([0.944, 1.0]), 0, progress=False)


def test_too_many_harmonics_for_the_builders_samples_names_file_and_table():
    # no samples in the file: the builder's default (64 samples) cannot resolve 40 harmonics
    spec = parse_sweep(sweep_text(harmonics=40, samples=""), "big.toml")
    with pytest.raises(InputError, match=r"big\.toml: \[sweep\] harmonics: .*samples"):
        spec.plan()


def test_harmonics_beyond_the_limit_is_refused_naming_file_and_table():
    with pytest.raises(InputError, match=r"big\.toml: \[sweep\] harmonics: 100000 .*at most"):
        parse_sweep(sweep_text(harmonics=100000, samples="samples = 200001"), "big.toml")


def test_overflowing_model_gives_failed_points_with_a_reason():
    # eccentricity = 1e300 overflowed: every point "solved", residual NaN, max Re ~ 1e150
    model = pendulum(samples=24, eccentricity=1e300)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow warnings reach the user either
        ds = sweep(model, W0 * np.array([0.5, 1.0]), 4, progress=False)
    assert (ds["status"].values == STATUS_FAILED).all()
    assert ds.attrs["failed_points"] == 2
    assert all("non-finite" in str(m) for m in ds["message"].values)
    assert not ds["stable"].values.any()
    assert np.isnan(ds["max_real_exponent"].values).all() and np.isnan(ds["amplitude"].values).all()


def test_overflowing_sweep_file_counts_failed_points(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "ecc.toml").write_text(sweep_text(parameters="[model.parameters]\neccentricity = 1e300"))
    assert main(["sweep", "ecc.toml", "--out", "ecc.nc", "--workers", "1", "-q"]) == 0
    ds = load(tmp_path / "ecc.nc")
    assert ds.attrs["failed_points"] == 2 and (ds["status"].values == STATUS_FAILED).all()


def test_resume_never_overwrites_a_finished_result_made_with_other_settings(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "p.toml").write_text(sweep_text())
    assert main(["sweep", "p.toml", "--out", "p.nc", "--workers", "1", "-q"]) == 0
    before = (tmp_path / "p.nc").read_bytes()
    code = main(["sweep", "p.toml", "--out", "p.nc", "--workers", "1", "-q", "--resume", "--omega", "0.5:0.6:3"])
    err = capsys.readouterr().err
    assert code == 2
    assert "p.nc" in err and "other settings" in err and "--out" in err
    assert (tmp_path / "p.nc").read_bytes() == before
    # the same settings resume to the finished file without recomputing
    mtime = os.stat(tmp_path / "p.nc").st_mtime_ns
    assert main(["sweep", "p.toml", "--out", "p.nc", "--workers", "1", "-q", "--resume"]) == 0
    assert os.stat(tmp_path / "p.nc").st_mtime_ns == mtime


def test_sweep_file_harmonics_limit_is_named_when_loading(tmp_path):
    path = tmp_path / "h.toml"
    path.write_text(sweep_text(harmonics=-1))
    with pytest.raises(InputError, match=r"h\.toml: \[sweep\] harmonics"):
        load_sweep_file(path)


def test_a_convergence_error_of_a_speed_batch_fails_only_its_own_speed(monkeypatch):
    """A solver that raises for one speed of a chunk: that speed is a failed point with the
    solver's message, the other speeds of the chunk are solved as without it."""
    from periodyn.speeds import SpeedSolver
    from periodyn.errors import ConvergenceError

    model = pendulum(samples=24)
    omega = W0 * np.array([0.5, 0.7, 1.2])
    reference = sweep(model, omega, 4, progress=False)
    solve_many = SpeedSolver.solve_many

    def failing(self, omegas):
        if np.any(np.isclose(omegas, omega[1])):
            raise ConvergenceError("Newton did not converge (residual 1e-2 after 30 iterations)")
        return solve_many(self, omegas)

    monkeypatch.setattr(SpeedSolver, "solve_many", failing)
    ds = sweep(model, omega, 4, progress=False)
    assert list(ds["status"].values) == [0, STATUS_FAILED, 0]
    assert "Newton did not converge" in str(ds["message"].values[1])
    np.testing.assert_array_equal(ds["amplitude"].values[[0, 2]], reference["amplitude"].values[[0, 2]])
