"""Every shipped study file runs through ``periodyn sweep`` at reduced size and writes a
results file that loads: speed sweeps with a few speeds, continuation studies from small
copies (fewer harmonics, rods and points), transients with fewer times, Campbell studies
at their own speeds or a few."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from periodyn.cli import main
from periodyn.studies.spec import load_sweep_file, project_root
from periodyn.results import load
from periodyn.studies.continuation import load_study

FILES = sorted((project_root() / "sweeps").glob("*.toml"))


def small_study(path: Path, folder: Path, harmonics: int = 3, max_points: int = 12) -> Path:
    """A copy of a study file with fewer harmonics, rods and points per branch, without its
    time history (the rod pendulum settles over 158 periods first; tests/integration/test_figures.py
    computes every time history of the shipped studies)."""
    text = re.sub(r"(?m)^(max_points|time_history) = .*\n", "", path.read_text())
    text = re.sub(r"(?m)^harmonics = \d+", f"harmonics = {harmonics}\nmax_points = {max_points}", text)
    text = re.sub(r"(?m)^n_rods = \d+", "n_rods = 2", text)
    text = re.sub(r"max_points = 150", "max_points = 5", text)
    out = folder / path.name
    out.write_text(text)
    return out


def test_every_shipped_file_is_covered():
    kinds = {load_sweep_file(p).kind for p in FILES}
    assert kinds == {"sweep", "continuation", "transient", "campbell", "chart"}


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_shipped_file_runs_at_reduced_size(path, tmp_path, capsys):
    spec = load_sweep_file(path)
    out = tmp_path / f"{path.stem}.nc"
    if spec.kind == "sweep":
        speeds = spec.omega_values()
        code = main(["sweep", str(path), "--omega", f"{speeds[0]}:{speeds[-1]}:3", "--out", str(out),
                     "--workers", "1", "-q"])
        assert code == 0, capsys.readouterr().err
        ds = load(out)
        assert ds.sizes["omega"] == 3
        assert np.isfinite(ds["omega"].values).all()
        return
    if spec.kind == "campbell":  # given speeds as they are, a range by 3 speeds
        reduced = [] if "values" in spec.speeds else ["--omega", f"{spec.speeds['stop'] / 2}:{spec.speeds['stop']}:3"]
        code = main(["sweep", str(path), "--out", str(out), "-q", *reduced])
        assert code == 0, capsys.readouterr().err
        ds = load(out)
        assert ds.sizes["speed"] == (len(spec.speeds["values"]) if not reduced else 3)
        assert np.isfinite(ds["frequency"].values).all() and set(np.unique(ds["whirl"].values)) <= {"forward", "backward"}
        return
    if spec.kind == "transient":  # one speed: fewer times
        small = tmp_path / path.name
        small.write_text(re.sub(r"(?m)^points = \d+", "points = 21", path.read_text()))
        code = main(["sweep", str(small), "--out", str(out), "-q"])
        assert code == 0, capsys.readouterr().err
        ds = load(out)
        assert ds.sizes["time"] == 21 and ds.attrs["omega"] == pytest.approx(spec.omega, rel=1e-15)
        assert np.isfinite(ds["outputs"].values).all()
        assert main(["sweep", str(small), "--out", str(out), "--omega", "1:2:3"]) == 2  # one speed: refused
        assert "transient study at one speed" in capsys.readouterr().err
        return
    if spec.kind == "chart":  # two parameter values, the top 5 % of the range: one step, one check per boundary
        small = tmp_path / path.name
        start = float(0.95 * spec.parameter_grid[-1] + 0.05 * spec.parameter_grid[0])
        text = re.sub(r"start = [0-9.e-]+, stop = ([0-9.e-]+), num = \d+ }", rf"start = {start!r}, stop = \1, num = 2 }}",
                      path.read_text(), count=1)
        small.write_text(re.sub(r"(?m)^checks = \d+", "checks = 1", text))
        code = main(["sweep", str(small), "--out", str(out), "-q"])
        assert code == 0, capsys.readouterr().err
        ds = load(out)
        assert ds.sizes["parameter_grid"] == 2 and ds.sizes["boundary"] >= 1 and ds["check_agrees"].values.all()
        return
    small = small_study(path, tmp_path)
    a, b = spec.omega
    stop = a + 0.25 * (b - a)
    code = main(["sweep", str(small), "--omega", f"{a}:{stop}:2", "--out", str(out), "--plot", str(tmp_path / "p.png")])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    ignored = "NUM (2) is ignored" if spec.speeds is None else "by 2 speeds from"
    assert ignored in captured.err and f"wrote {out}" in captured.out
    assert (tmp_path / "p.png").stat().st_size > 0
    branches = load_study(out)
    expected = {"frequency"} | ({"parameter"} if spec.parameter else set())
    assert expected <= set(branches) <= expected | {"period_doubled"}
    freq = branches["frequency"]
    assert 2 <= len(freq) <= 12
    assert freq.omega[0] == pytest.approx(a, rel=1e-6)  # the first point sits at the range start
    assert np.all(freq.residual < 1e-6)
    # --omega a:stop replaced the file's range: the branch ends once it passes stop (last step)
    assert freq.omega[:-1].max() < stop < b
    if spec.speeds is not None:  # given speeds: exactly a and stop
        np.testing.assert_allclose(freq.omega, [a, stop], rtol=1e-15)
    else:
        assert freq.status.startswith("max_points reached") or freq.omega[-1] >= stop
    if freq.status.startswith("max_points reached"):  # the CLI prints why the branch ended and what to change
        assert "raise max_points" in captured.err
    assert freq.solutions[0].harmonics.shape[0] == 2 * 3 + 1
    if spec.parameter:
        par = branches["parameter"]
        assert par.parameter_name == spec.parameter["name"]
        np.testing.assert_allclose(par.omega, spec.parameter["omega"])
        assert par.parameter[0] == pytest.approx(spec.parameter["start"], rel=1e-6)


def test_study_resume_reuses_the_same_settings_and_refuses_others(tmp_path, capsys):
    small = small_study(project_root() / "sweeps" / "dae_rod_pendulum.toml", tmp_path, harmonics=2, max_points=4)
    out = tmp_path / "rod.nc"
    assert main(["sweep", str(small), "--omega", "3.0:3.3:2", "--out", str(out), "-q"]) == 0
    stamp = out.stat().st_mtime_ns
    first = load_study(out)
    assert main(["sweep", str(small), "--omega", "3.0:3.3:9", "--out", str(out), "--resume", "-q"]) == 0
    assert out.stat().st_mtime_ns == stamp  # reused: NUM does not change a study
    np.testing.assert_array_equal(load_study(out)["frequency"].amplitude, first["frequency"].amplitude)
    capsys.readouterr()
    assert main(["sweep", str(small), "--omega", "3.0:3.2:2", "--out", str(out), "--resume", "-q"]) == 2
    err = capsys.readouterr().err
    assert "finished study made with other settings" in err and "drop --resume" in err
    assert out.stat().st_mtime_ns == stamp
    small.write_text(small.read_text().replace("eps1 = 0.04", "eps1 = 0.05"))
    assert main(["sweep", str(small), "--omega", "3.0:3.3:2", "--out", str(out), "--resume", "-q"]) == 2
    assert main(["sweep", str(small), "--omega", "3.0:3.3:2", "--out", str(out), "-q"]) == 0  # replaced
    assert out.stat().st_mtime_ns != stamp


def test_study_result_file_is_not_a_sweep_and_back(tmp_path, capsys):
    sweep = next(p for p in FILES if p.stem == "pendulum")
    out = tmp_path / "x.nc"
    assert main(["sweep", str(sweep), "--omega", "0.5:0.6:2", "--out", str(out), "--workers", "1", "-q"]) == 0
    small = small_study(project_root() / "sweeps" / "dae_rod_pendulum.toml", tmp_path, harmonics=2, max_points=3)
    assert main(["sweep", str(small), "--out", str(out), "--resume", "-q"]) == 2
    assert "not a continuation study result" in capsys.readouterr().err


@pytest.mark.parametrize(
    "edit, message",
    [
        (("harmonics = 10", "harmonics = 0"), r"\[continuation\] harmonics: must be an integer >= 1"),
        (("unit = \"rad/s\"", "unit = \"omega0\""), r"\[continuation\] omega.unit: unknown unit 'omega0'"),
        (("harmonics = 10", "harmonics = 10\nmethod = \"hb\""), r"unknown method 'hb'; choose one of: ihb, shooting"),
        (("harmonics = 10", "harmonics = 10\nstability = \"magnu\""), r"stability: must be one of magnus"),
        (("name = \"f\"", "name = \"F\""), r"parameter.name: 'F' is not set in \[model.parameters\]"),
        (("harmonics = 10", "harmonics = 10\nds_mx = 0.1"), r"unknown key 'ds_mx'; did you mean 'ds_max'\?"),
        (("[continuation]", "[sweep]\nomega = { values = [1.0], unit = \"rad/s\" }\nharmonics = 3\n[continuation]"),
         r"top level: give one of \[sweep\] .* not \[sweep\] and \[continuation\]"),
    ],
)
def test_bad_study_files_exit_2_naming_table_and_fix(tmp_path, capsys, edit, message):
    text = (project_root() / "sweeps" / "dae_rod_pendulum.toml").read_text()
    assert edit[0] in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(edit[0], edit[1], 1))
    assert main(["sweep", str(bad), "--out", str(tmp_path / "bad.nc")]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and re.search(message, err), err


def test_speed_sweep_example_in_a_study_is_refused(tmp_path, capsys):
    bad = tmp_path / "pend.toml"
    bad.write_text('[model]\nexample = "pendulum"\n[continuation]\n'
                   'omega = { start = 1.0, stop = 2.0, unit = "rad/s" }\nharmonics = 3\n')
    assert main(["sweep", str(bad), "--out", str(tmp_path / "p.nc")]) == 2
    assert "pendulum is not a DAE example; use [sweep]" in capsys.readouterr().err


def test_ensure_gives_the_branches_of_a_study_and_reuses_them(tmp_path, monkeypatch):
    from periodyn.studies.spec import ensure

    (tmp_path / "sweeps").mkdir()
    small = small_study(project_root() / "sweeps" / "dae_rod_pendulum.toml", tmp_path / "sweeps", 2, 4)
    monkeypatch.chdir(tmp_path)
    branches = ensure(small.stem)
    out = tmp_path / "results" / f"{small.stem}.nc"
    stamp = out.stat().st_mtime_ns
    again = ensure(small.stem)
    assert out.stat().st_mtime_ns == stamp and set(again) == set(branches) == {"frequency", "parameter"}
    np.testing.assert_array_equal(again["frequency"].omega, branches["frequency"].omega)
    small.write_text(small.read_text().replace("max_points = 4", "max_points = 5"))
    assert len(ensure(small.stem)["frequency"]) == 5  # another version of the file: computed again


def test_study_at_given_speeds_is_pointwise_shooting(tmp_path):
    """omega.values: one orbit per given speed, in the order given, each the orbit that
    shooting finds on its own at that speed (the same spectra and multipliers)."""
    from periodyn.examples import duffing
    from periodyn.nonlinear import shooting

    study = tmp_path / "duffing_points.toml"
    study.write_text('[model]\nexample = "duffing"\n[model.parameters]\nF = 0.3\n[continuation]\n'
                     'omega = { values = [0.8, 1.3, 1.05], unit = "rad/s" }\nharmonics = 5\nmethod = "shooting"\n')
    out = tmp_path / "points.nc"
    assert main(["sweep", str(study), "--out", str(out), "-q"]) == 0
    freq = load_study(out)["frequency"]
    np.testing.assert_array_equal(freq.omega, [0.8, 1.3, 1.05])
    assert freq.status.startswith("solutions at 3 given speeds")
    for k, w in enumerate(freq.omega):
        alone = shooting(duffing(F=0.3), w, samples=11)
        np.testing.assert_allclose(freq.solutions[k].harmonics, alone.harmonics, atol=1e-8)
        np.testing.assert_allclose(np.sort(np.abs(freq.solutions[k].multipliers)), np.sort(np.abs(alone.multipliers)),
                                   rtol=1e-6)
        assert freq.stable[k] == alone.stable and freq.residual[k] < 1e-9


def test_given_speeds_refuse_a_parameter_curve(tmp_path, capsys):
    text = (project_root() / "sweeps" / "dae_rod_pendulum.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('omega = { start = 2.5, stop = 5.0, unit = "rad/s" }',
                                'omega = { values = [2.5, 3.0], unit = "rad/s" }'))
    assert main(["sweep", str(bad), "--out", str(tmp_path / "bad.nc")]) == 2
    assert "[continuation] parameter: needs a continuation over omega = { start, stop }" in capsys.readouterr().err


def test_a_damaged_study_file_is_a_read_error_naming_it(tmp_path, capsys):
    """Continuation study files carry the checksums of every result file (Fletcher-32 per
    variable, a SHA-256 digest): inverted bytes in a branch's data are a clear error on
    load and on --resume, never a wrong branch."""
    import h5py

    from periodyn.errors import InputError

    small = small_study(project_root() / "sweeps" / "dae_rod_pendulum.toml", tmp_path, harmonics=2, max_points=4)
    out = tmp_path / "rod.nc"
    assert main(["sweep", str(small), "--omega", "3.0:3.3:2", "--out", str(out), "-q"]) == 0
    load_study(out)
    with h5py.File(out, "r") as f:
        assert "periodyn_sha256" in f.attrs and f["frequency/amplitude"].fletcher32
        info = f["frequency/amplitude"].id.get_chunk_info(0)
    data = bytearray(out.read_bytes())
    end = info.byte_offset + min(info.size, 4096)
    data[info.byte_offset:end] = bytes(b ^ 0xFF for b in data[info.byte_offset:end])
    out.write_bytes(bytes(data))
    with pytest.raises(InputError, match=f"{out} is not a readable periodyn result file, or it is damaged"):
        load_study(out)
    capsys.readouterr()
    assert main(["sweep", str(small), "--omega", "3.0:3.3:2", "--out", str(out), "--resume", "-q"]) == 2
    err = capsys.readouterr().err
    assert "damaged" in err and str(out) in err and "Traceback" not in err
