"""A real sweep process killed with SIGKILL resumes to the uninterrupted result, and Dask
clusters give the same results as the serial sweep."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from periodyn.studies.spec import load_sweep_file
from periodyn.engine import backends
from periodyn.examples import pendulum
from periodyn.engine.front import ExecutionOptions, sweep, sweep_file
from tests.integration.datasets import pendulum_sweep_text, without_attrs

# long enough (dense Hill, ~10 s on one core) that the sweep is still running once its worker
# has started: the sweep's own process never waits for a worker still starting
SPEEDS = 6000
KILL_SWEEP = pendulum_sweep_text(SPEEDS, "sweep that is killed mid-run by the test")
CHUNK = 20


def descendants(pid: int) -> list[int]:
    """Child processes, their children, ... (workers may be forked by a fork server)."""
    path = Path(f"/proc/{pid}/task/{pid}/children")
    kids = [int(c) for c in path.read_text().split()] if path.exists() else []
    return kids + [d for k in kids for d in descendants(k)]


def alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    stat = Path(f"/proc/{pid}/stat")
    return not (stat.exists() and stat.read_text().split(") ")[-1].startswith("Z"))


def test_sigkill_mid_sweep_then_resume_equals_uninterrupted(tmp_path):
    sweep_path = tmp_path / "kill.toml"
    sweep_path.write_text(KILL_SWEEP)
    out = tmp_path / "kill.nc"
    parts = tmp_path / "kill.nc.parts"
    proc = subprocess.Popen([sys.executable, "-m", "periodyn.cli", "sweep", str(sweep_path), "--out", str(out),
                             "--workers", "2", "--chunk-size", str(CHUNK), "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    # the sweep's own process solves chunks too: wait for checkpoints and for the fork server's worker
    while len(list(parts.glob("chunk-*.npz"))) < 3 or len(descendants(proc.pid)) < 2:
        assert proc.poll() is None, proc.stderr.read().decode()
        assert time.monotonic() < deadline, "the sweep wrote no checkpoints or started no worker"
        time.sleep(0.005)
    workers = descendants(proc.pid)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert proc.returncode == -signal.SIGKILL
    done_before = len(list(parts.glob("chunk-*.npz")))
    assert not out.exists() and 3 <= done_before < SPEEDS // CHUNK

    spec = load_sweep_file(sweep_path)
    progress = []
    resumed = sweep_file(spec, out=out, resume=True, chunk_size=CHUNK, progress=lambda d, t: progress.append(d))
    assert progress[0] >= (done_before + 1) * CHUNK  # checkpointed points were not recomputed
    assert not parts.exists() and out.is_file()
    uninterrupted = sweep_file(spec, progress=False)
    xr.testing.assert_identical(without_attrs(resumed), without_attrs(uninterrupted))

    deadline = time.monotonic() + 20
    while any(alive(pid) for pid in workers) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not any(alive(pid) for pid in workers), "worker processes outlived the killed sweep"


@pytest.fixture(scope="module")
def small():
    model = pendulum(samples=24)
    omega = np.sqrt(9.81) * np.linspace(0.2, 1.3, 30)
    return model, omega, without_attrs(sweep(model, omega, 5, progress=False))


def test_dask_cluster_address_matches_serial(small):
    from distributed import LocalCluster

    model, omega, serial = small
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        ds = sweep(model, omega, 5, execution=ExecutionOptions(cluster.scheduler_address, 4), progress=False)
    assert ds.attrs["backend"] == "dask"
    xr.testing.assert_identical(without_attrs(ds), serial)


def test_dask_local_cluster_matches_serial(small):
    model, omega, serial = small
    ds = sweep(model, omega, 5, workers=2, execution=ExecutionOptions("local", 4), progress=False)
    xr.testing.assert_identical(without_attrs(ds), serial)


def test_script_without_main_guard_runs_workers_once(tmp_path):
    """Workers get the job by cloudpickle; the caller's script is not executed again in them."""
    script = tmp_path / "unguarded.py"
    script.write_text(
        "import numpy as np\n"
        "from periodyn.examples import pendulum\n"
        "from periodyn import ExecutionOptions, sweep\n"
        "print('script body ran', flush=True)\n"
        "ds = sweep(lambda w: pendulum(samples=16).at(w), np.linspace(1.0, 2.0, 6), 3, workers=2,\n"
        "           execution=ExecutionOptions(chunk_size=2, eager_workers=True),\n"
        "           progress=False)\n"
        "print('stable points:', int(ds['stable'].sum()), flush=True)\n")
    run = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.count("script body ran") == 1 and "stable points: 6" in run.stdout


SHIPPED = sorted(p.stem for p in (Path(__file__).resolve().parents[2] / "sweeps").glob("*.toml")
                 if load_sweep_file(p).kind == "sweep")  # continuation studies have no speed grid


@pytest.mark.parametrize("name", SHIPPED)
def test_serial_and_two_workers_bit_identical_on_shipped_sweeps(name, monkeypatch):
    """Each shipped sweep file at 12 speeds of its range: the serial sweep (in this process,
    where BLAS would otherwise run several threads) equals two worker processes bit for bit
    (started although the sweep is short)."""
    monkeypatch.setattr(backends, "START_COST", {"first": 0.0, "later": 0.0})
    spec = load_sweep_file(Path(__file__).resolve().parents[2] / "sweeps" / f"{name}.toml")
    speeds = spec.omega_values()
    omega = (float(speeds.min()), float(speeds.max()), 12)
    serial = sweep_file(spec, omega=omega, workers=1, progress=False)
    parallel = sweep_file(spec, omega=omega, workers=2, chunk_size=3, progress=False)
    assert parallel.attrs["backend"] == "processes"
    xr.testing.assert_identical(without_attrs(serial), without_attrs(parallel))
