"""The periodyn command line: sweep, figures, bench, info, help and exit codes."""

from __future__ import annotations

import subprocess
import sys
import textwrap

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
        from periodyn.config import ensure

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
    assert "12 points, 0 failed" in out and "unstable (or failed) points, ω / ω0: [0.9" in out


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
    for argv in ([], ["sweep"], ["figures"], ["bench"], ["info"]):
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
