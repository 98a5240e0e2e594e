"""The periodyn command line: sweep, figures, bench, info, help and exit codes."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from periodyn.cli import main
from periodyn.results import load

TINY = """
description = "tiny pendulum sweep"
[model]
example = "pendulum"
[sweep]
omega = { start = 0.3, stop = 1.2, num = 30, unit = "omega0" }
harmonics = 5
samples = 24
"""


@pytest.fixture
def project(tmp_path, monkeypatch):
    """A project folder with one sweep file, one figure script and one benchmark."""
    (tmp_path / "sweeps").mkdir()
    (tmp_path / "sweeps" / "tiny.toml").write_text(TINY)
    (tmp_path / "figures").mkdir()
    (tmp_path / "figures" / "fig9_tiny.py").write_text(textwrap.dedent("""
        from periodyn.plotting import plot_sweep, save_figure
        from periodyn.studies.spec import ensure

        def main(out_dir):
            return [save_figure(plot_sweep(ensure("tiny")), out_dir / "fig9_tiny.png")]
        """))
    (tmp_path / "benchmarks").mkdir()
    (tmp_path / "benchmarks" / "bench_hello.py").write_text("print('hello from a benchmark')\n")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_sweep_writes_results_and_plot(project, capsys):
    code = main(["sweep", "sweeps/tiny.toml", "--omega", "0.4:1.1:12", "--out", "r/tiny.nc", "--plot", "r/tiny.png"])
    assert code == 0
    ds = load(project / "r" / "tiny.nc")
    np.testing.assert_allclose(ds["omega_over_omega0"].values, np.linspace(0.4, 1.1, 12), rtol=1e-12)
    assert ds.attrs["sweep_file_text"] == TINY
    assert (project / "r" / "tiny.png").stat().st_size > 10_000
    out = capsys.readouterr().out
    assert "12 points, 0 failed" in out and "unstable (or failed) points, ω / ω0 (ω0 = 3.132 rad/s): [0.9" in out


def test_sweep_default_output_and_quiet(project, capsys):
    assert main(["sweep", "sweeps/tiny.toml", "--quiet", "--workers", "1"]) == 0
    assert (project / "results" / "tiny.nc").is_file()
    assert capsys.readouterr() == ("", "")


@pytest.mark.parametrize(
    "argv, message",
    [
        (["sweep", "sweeps/nope.toml"], "no sweep file at sweeps/nope.toml; files in sweeps: bad.toml, tiny.toml"),
        (["sweep", "sweeps/bad.toml"], "unknown key 'harmonic'; did you mean 'harmonics'?"),
        (["figures", "fig7"], "no script matches 'fig7'; available: fig9_tiny"),
    ],
)
def test_bad_input_exits_2_with_a_message(project, capsys, argv, message):
    (project / "sweeps" / "bad.toml").write_text(TINY.replace("harmonics", "harmonic"))
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_argument_errors_exit_2(capsys):
    with pytest.raises(SystemExit) as info:
        main(["sweep", "x.toml", "--omega", "1:2"])
    assert info.value.code == 2
    assert "--omega takes start:stop:num" in capsys.readouterr().err


def test_figures_and_bench_run_scripts(project, capsys):
    assert main(["figures", "--list"]) == 0
    assert capsys.readouterr().out.strip() == "fig9_tiny"
    assert main(["figures", "fig9"]) == 0
    assert (project / "figures" / "png" / "fig9_tiny.png").is_file()
    assert (project / "results" / "tiny.nc").is_file()  # ensure() computed the sweep
    assert main(["bench", "hello"]) == 0
    capsys.readouterr()


def test_failing_figure_script_is_reported(project, capsys):
    (project / "figures" / "fig1_broken.py").write_text("def main(out_dir):\n    raise RuntimeError('no data')\n")
    assert main(["figures", "fig1"]) == 1
    assert "fig1_broken: FAILED (RuntimeError: no data)" in capsys.readouterr().err


def test_info(capsys):
    assert main(["info"]) == 0
    out = capsys.readouterr().out
    for word in ("numpy", "numba:", "BLAS:", "FFTW", "cores:"):
        assert word in out


def test_help_of_every_command(capsys):
    for argv in ([], ["sweep"], ["figures"], ["bench"], ["warmup"], ["info"]):
        with pytest.raises(SystemExit) as info:
            main([*argv, "--help"])
        assert info.value.code == 0 and "usage: periodyn" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["sweep", "--help"])
    sweep_help = capsys.readouterr().out
    for option in ("--omega", "--out", "--plot", "--resume", "--workers", "--scheduler", "--chunk-size", "--quiet"):
        assert option in sweep_help


def test_console_entry_point_runs():
    run = subprocess.run([sys.executable, "-m", "periodyn.cli", "--help"], capture_output=True, text=True)
    assert run.returncode == 0 and "sweep" in run.stdout and "figures" in run.stdout


def test_figures_report_progress_per_script(project, capsys):
    assert main(["figures", "fig9"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "[1/1] fig9_tiny ..."
    assert lines[-1].startswith("[1/1] fig9_tiny (") and lines[-1].endswith("fig9_tiny.png")


def test_plot_axes_and_result_file_carry_units(project, capsys):
    (project / "sweeps" / "tiny.toml").write_text(TINY + 'output_units = { phi = "rad" }\n')
    assert main(["sweep", "sweeps/tiny.toml", "--out", "r.nc", "--plot", "r.png", "-q", "--workers", "1"]) == 0
    ds = load(project / "r.nc")
    assert ds["amplitude"].attrs["units"] == "rad" and list(ds["output_units"].values) == ["rad"]
    assert ds["output"].attrs["long_name"] and ds["omega_over_omega0"].attrs["reference_frequency_units"] == "rad/s"
    import matplotlib.pyplot as plt

    from periodyn.plotting import plot_sweep

    fig = plot_sweep(ds, title="tiny")
    top, bottom = fig.axes[:2]
    assert top.get_ylabel().endswith("[rad]") and bottom.get_ylabel() == "max Re λ [1/s]"
    assert "ω0 = 3.132 rad/s" in bottom.get_xlabel()
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any(t.startswith("unstable band") for t in legend) and "unstable point" in legend
    plt.close(fig)


def test_summary_after_resume_counts_computed_points(project, capsys):
    from periodyn.studies.spec import load_sweep_file
    from periodyn.engine.front import ExecutionOptions, OutputOptions, sweep

    spec = load_sweep_file(project / "sweeps" / "tiny.toml")
    plan = spec.plan()
    out = project / "part.nc"

    class Stop(Exception):
        pass

    def stop(done, total):
        if done >= 10:
            raise Stop

    with pytest.raises(Stop):
        sweep(plan.model, plan.omega, spec.harmonics, spec.samples, out=out, progress=stop,
              execution=ExecutionOptions(chunk_size=5),
              output=OutputOptions(spec.example, plan.reference, None, spec.text))
    assert main(["sweep", "sweeps/tiny.toml", "--out", "part.nc", "--resume", "--workers", "1",
                 "--chunk-size", "5"]) == 0
    out_text = capsys.readouterr().out
    assert "30 points, 10 restored from checkpoints" in out_text and "points/s computed" in out_text
    assert load(out).attrs["points_computed"] == 20


def test_descending_speeds_get_a_note(project, capsys):
    assert main(["sweep", "sweeps/tiny.toml", "--omega", "1.2:0.4:5", "--out", "d.nc", "--workers", "1"]) == 0
    assert "note: the speeds run down, from 1.2 to 0.4 omega0" in capsys.readouterr().err


def test_warmup_reports_each_step(capsys):
    from periodyn.engine.warmup import STEPS

    assert main(["warmup"]) == 0
    out = capsys.readouterr().out.splitlines()
    k = len(STEPS)
    steps = sorted(line for line in out if line.startswith("warmup ["))  # as they finish, in parallel processes
    assert k == 6 and len(steps) == k and all(line.startswith(f"warmup [{i}/{k}] ") and line.endswith(" s")
                                              for i, line in enumerate(steps, 1))
    assert out[-1].startswith("kernels compiled and cached in")


def test_bench_linearize_runs_without_the_test_extras(tmp_path):
    """benchmarks/bench_linearize.py imports its NumPy twin from tests/twins/planar.py,
    which needs neither pytest nor hypothesis (both made unimportable here)."""
    root = Path(__file__).resolve().parents[2]
    blocker = tmp_path / "sitecustomize.py"
    blocker.write_text("import sys\nfor name in ('pytest', 'hypothesis', '_pytest'):\n    sys.modules[name] = None\n")
    env = {**os.environ, "PYTHONPATH": f"{tmp_path}:{root / 'src'}"}
    run = subprocess.run([sys.executable, "-c", "import runpy, sys; sys.argv = ['bench_linearize.py', '--help']; "
                          f"runpy.run_path({str(root / 'benchmarks' / 'bench_linearize.py')!r}, run_name='__main__')"],
                         capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "usage" in run.stdout


def test_a_cold_kernel_cache_is_announced_before_the_sweep(project, capsys, monkeypatch):
    import importlib

    engine = importlib.import_module("periodyn.engine.front")
    monkeypatch.setattr(engine, "kernels_cached", lambda: False)
    assert main(["sweep", "sweeps/tiny.toml", "--out", "c.nc", "--workers", "1"]) == 0
    assert "compiling the numerical kernels on first use" in capsys.readouterr().err
    assert main(["sweep", "sweeps/tiny.toml", "--out", "c.nc", "--workers", "1", "-q"]) == 0
    assert capsys.readouterr().err == ""  # --quiet says nothing


def test_kernels_cached_sees_the_cache_beside_the_sources():
    from periodyn.engine.warmup import kernels_cached, warm_up

    with open(os.devnull, "w") as sink:
        warm_up(sink)
    assert kernels_cached()
