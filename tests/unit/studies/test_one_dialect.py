"""One dialect and one cache rule for every study kind: every shipped study file parses
with the one entry, the cheap ones run at a reduced range through ``periodyn sweep``,
and a result is current iff its fingerprint equals the request's."""

from __future__ import annotations

import numpy as np
import pytest

from periodyn.cli import main
from periodyn.results import load
from periodyn.studies import cache
from periodyn.studies.spec import KINDS, ensure, load_sweep_file, parse_sweep, project_root

FILES = sorted((project_root() / "sweeps").glob("*.toml"))
ROTOR = project_root() / "sweeps" / "rotors" / "table1.toml"
CAMPBELL = f"""
description = "a few speeds"
[model]
rotor = "{ROTOR.as_posix()}"
[campbell]
speeds = {{ start = 0.0, stop = 6000.0, num = 4, unit = "rpm" }}
modes = 4
"""


def test_every_shipped_file_parses_with_the_one_entry_and_every_kind_ships():
    kinds = {path.stem: load_sweep_file(path).kind for path in FILES}
    assert set(kinds.values()) == set(KINDS) == {"sweep", "continuation", "transient", "campbell", "chart"}
    assert kinds["rotor_campbell"] == "campbell"
    assert load_sweep_file(project_root() / "sweeps" / "pendulum.toml").boundaries


@pytest.mark.parametrize("name", ["rotor_campbell", "rotor_table1", "pendulum"])
def test_cheap_shipped_files_run_at_a_reduced_range(name, tmp_path, capsys):
    """The cheap shipped files (the slider-crank transients and the continuation studies
    run in tests/unit/test_study_files.py)."""
    path = project_root() / "sweeps" / f"{name}.toml"
    spec = load_sweep_file(path)
    out = tmp_path / f"{name}.nc"
    if spec.kind == "sweep":
        args = ["--omega", "0.85:1.1:6", "--workers", "1"]
    else:
        args = [] if "values" in spec.speeds else ["--omega", "1000:4000:3"]
    assert main(["sweep", str(path), "--out", str(out), "-q", *args]) == 0, capsys.readouterr().err
    ds = load(out)
    assert ds.attrs[cache.KIND] == spec.kind and cache.is_current(out, load_sweep_file(path), _range(args))


def test_a_transient_study_runs_and_resumes_by_the_same_rule(tmp_path, capsys):
    study = tmp_path / "t.toml"
    study.write_text('[model]\nexample = "pendulum"\n[transient]\nomega = { value = 2.0, unit = "rad/s" }\n'
                     'harmonics = 4\npoints = 11\nsamples = 16\n')
    out = tmp_path / "t.nc"
    assert main(["sweep", str(study), "--out", str(out), "-q", "--plot", str(tmp_path / "t.png")]) == 0
    ds = load(out)
    assert list(ds["method"].values) == ["averaging", "integrate"] and ds.sizes["time"] == 11
    assert ds.attrs[cache.KIND] == "transient" and cache.is_current(out, load_sweep_file(study))
    stamp = out.stat().st_mtime_ns
    assert main(["sweep", str(study), "--out", str(out), "-q", "--resume"]) == 0 and out.stat().st_mtime_ns == stamp
    study.write_text(study.read_text().replace("points = 11", "points = 12"))
    capsys.readouterr()
    assert main(["sweep", str(study), "--out", str(out), "-q", "--resume"]) == 2
    assert "finished study made with other settings" in capsys.readouterr().err


def _range(args):
    if "--omega" not in args:
        return None
    a, b, n = args[args.index("--omega") + 1].split(":")
    return float(a), float(b), int(n)


def test_campbell_study_writes_the_campbell_dataset_and_plots(tmp_path, capsys):
    from periodyn.examples import rotor
    from periodyn.rotor import campbell

    study = tmp_path / "c.toml"
    study.write_text(CAMPBELL)
    out = tmp_path / "c.nc"
    assert main(["sweep", str(study), "--out", str(out), "--plot", str(tmp_path / "c.png")]) == 0
    assert "Campbell diagram, 4 speeds x 4 modes" in capsys.readouterr().out
    assert (tmp_path / "c.png").stat().st_size > 10_000
    ds = load(out)
    direct = campbell(rotor(), np.linspace(0.0, 6000.0, 4) * np.pi / 30.0, modes=4)
    np.testing.assert_allclose(ds["eigenvalue"].values, direct["eigenvalue"].values, rtol=1e-12)
    assert (ds["whirl"].values == direct["whirl"].values).all()
    np.testing.assert_equal(float(ds["threshold_speed"]), direct.attrs["threshold_speed"])


def test_campbell_grid_stacks_one_dataset_per_point(tmp_path):
    study = tmp_path / "g.toml"
    study.write_text(CAMPBELL + "[campbell.grid]\nelements = [1, 2]\n")
    out = tmp_path / "g.nc"
    assert main(["sweep", str(study), "--out", str(out), "-q"]) == 0
    ds = load(out)
    assert ds["eigenvalue"].dims == ("elements", "speed", "mode") and list(ds["elements"].values) == [1, 2]
    assert ds["threshold_speed"].dims == ("elements",)
    assert main(["sweep", str(study), "--out", str(out), "--plot", str(tmp_path / "g.png")]) == 2


def test_fingerprint_is_the_parsed_request_not_the_text(tmp_path):
    spec = parse_sweep(CAMPBELL, str(tmp_path / "c.toml"), "c")
    key = cache.fingerprint(spec)
    relaid = CAMPBELL.replace('description = "a few speeds"', 'description = "other words"  # a comment')
    assert cache.fingerprint(parse_sweep(relaid.replace("modes = 4", "modes   =   4"), "x.toml", "x")) == key
    assert cache.fingerprint(parse_sweep(CAMPBELL.replace("modes = 4", "modes = 3"), "x.toml", "x")) != key
    assert cache.fingerprint(spec, (1.0, 2.0, 3)) != key != cache.fingerprint(spec, (1.0, 2.0, 4))
    rotor = tmp_path / "r.toml"
    rotor.write_text(ROTOR.read_text())
    own = parse_sweep(CAMPBELL.replace(ROTOR.as_posix(), rotor.as_posix()), "x.toml", "x")
    before = cache.fingerprint(own)
    rotor.write_text(ROTOR.read_text().replace("elements = 5", "elements = 10"))
    assert cache.fingerprint(own) != before  # the rotor file changed: the result is stale


def test_resume_reads_a_current_result_and_refuses_one_made_otherwise(tmp_path, capsys):
    study = tmp_path / "c.toml"
    study.write_text(CAMPBELL)
    out = tmp_path / "c.nc"
    assert main(["sweep", str(study), "--out", str(out), "-q"]) == 0
    stamp = out.stat().st_mtime_ns
    assert main(["sweep", str(study), "--out", str(out), "-q", "--resume"]) == 0
    assert out.stat().st_mtime_ns == stamp  # current: read, not computed
    capsys.readouterr()
    assert main(["sweep", str(study), "--out", str(out), "-q", "--resume", "--omega", "10:20:2"]) == 2
    assert "finished study made with other settings" in capsys.readouterr().err
    other = tmp_path / "t.toml"
    other.write_text((project_root() / "sweeps" / "slider_crank_transient.toml").read_text())
    assert main(["sweep", str(other), "--out", str(out), "-q", "--resume"]) == 2
    assert "is not a transient study result (a campbell result made it)" in capsys.readouterr().err
    assert out.stat().st_mtime_ns == stamp


def test_ensure_reads_a_current_campbell_result_and_recomputes_a_stale_one(tmp_path, monkeypatch):
    (tmp_path / "sweeps").mkdir()
    (tmp_path / "sweeps" / "c.toml").write_text(CAMPBELL)
    monkeypatch.chdir(tmp_path)
    first = ensure("c")
    stamp = (tmp_path / "results" / "c.nc").stat().st_mtime_ns
    with monkeypatch.context() as m:
        m.setattr("periodyn.rotor.campbell", lambda *a, **k: pytest.fail("recomputed a current result"))
        again = ensure("c")
    assert (tmp_path / "results" / "c.nc").stat().st_mtime_ns == stamp
    np.testing.assert_array_equal(again["eigenvalue"].values, first["eigenvalue"].values)
    (tmp_path / "sweeps" / "c.toml").write_text(CAMPBELL.replace("num = 4", "num = 3"))
    assert ensure("c").sizes["speed"] == 3  # another request: computed again


def test_boundaries_are_results_of_the_sweep(tmp_path):
    """[sweep] boundaries = true stores each sign change of max Re(lambda), refined by
    stability_boundaries, with its type (fig03 only reads them)."""
    from periodyn.examples import pendulum
    from periodyn.stability.boundaries import stability_boundaries

    text = (project_root() / "sweeps" / "pendulum.toml").read_text()
    study = tmp_path / "p.toml"
    study.write_text(text)
    out = tmp_path / "p.nc"
    assert main(["sweep", str(study), "--omega", "0.8:1.1:7", "--out", str(out), "--workers", "1", "-q"]) == 0
    ds = load(out)
    w0 = float(ds["omega_over_omega0"].attrs["reference_frequency"])
    omega, stable = ds["omega"].values, ds["stable"].values
    flips = np.flatnonzero(stable[1:] != stable[:-1])
    assert ds.sizes["boundary"] == len(flips) == 2
    spec = load_sweep_file(study)
    model = pendulum(**spec.parameters, samples=spec.samples)
    for k, i in enumerate(flips):
        (direct,) = stability_boundaries(model.at, omega[i:i + 2], spec.harmonics)
        assert omega[i] < ds["boundary_omega"].values[k] < omega[i + 1]
        assert ds["boundary_omega"].values[k] == pytest.approx(direct.omega, rel=1e-12)
        assert ds["boundary_kind"].values[k] == direct.kind == "fold"
        assert bool(ds["boundary_becomes_stable"].values[k]) == direct.becomes_stable == bool(stable[i + 1])
    assert 0.91 < ds["boundary_omega"].values[0] / w0 < 0.93 and 1.01 < ds["boundary_omega"].values[1] / w0 < 1.03
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("stability = true", "stability = false"))
    assert main(["sweep", str(bad), "--out", str(tmp_path / "b.nc")]) == 2


@pytest.mark.parametrize("fault", ["truncated", "failed"])
def test_an_unreliable_boundary_refinement_is_flagged_not_raised(tmp_path, monkeypatch, fault):
    """A Hill verdict truncated (or a solve failing) inside the refinement, after the whole
    sweep is computed, gives a flagged boundary and a warning, not a traceback."""
    import warnings

    import periodyn.stability.boundaries as boundaries
    from periodyn.errors import ConvergenceError
    from periodyn.stability.floquet import TruncationWarning

    grid = np.linspace(0.8, 1.1, 7)
    exact = boundaries.characteristic_exponents

    def faulty(system, *args, **kwargs):  # fault at the refinement's inner speeds only
        inner = not np.isclose(system.omega / grid, 1.0, rtol=1e-9).any()
        if inner and fault == "failed":
            raise ConvergenceError("no convergence at an inner speed")
        if inner:
            warnings.warn("Hill's method is truncated at an inner speed", TruncationWarning)
        return exact(system, *args, **kwargs)

    text = (project_root() / "sweeps" / "pendulum.toml").read_text()
    study = tmp_path / "p.toml"
    study.write_text(text)
    clean = tmp_path / "clean.nc"
    assert main(["sweep", str(study), "--omega", "0.8:1.1:7", "--out", str(clean), "--workers", "1", "-q"]) == 0
    assert (load(clean)["boundary_message"].values == "").all()
    monkeypatch.setattr(boundaries, "characteristic_exponents", faulty)
    out = tmp_path / "p.nc"
    with pytest.warns(TruncationWarning, match="2 of 2 stability boundaries are not reliable"):
        assert main(["sweep", str(study), "--omega", "0.8:1.1:7", "--out", str(out), "--workers", "1", "-q"]) == 0
    ds = load(out)
    assert ds.sizes["boundary"] == 2 and all(fault in str(m) or "truncated" in str(m)
                                             for m in ds["boundary_message"].values)
    if fault == "failed":
        assert np.isnan(ds["boundary_omega"].values).all()
    else:
        assert ds["boundary_omega"].values == pytest.approx(load(clean)["boundary_omega"].values, rel=1e-12)
