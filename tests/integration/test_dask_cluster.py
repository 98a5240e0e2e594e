"""A Dask cluster started with Dask's own commands (``dask scheduler``, ``dask worker``) as
separate processes on localhost: ``periodyn sweep FILE --scheduler tcp://...`` survives a
worker killed (SIGKILL) mid-sweep, its chunks being retried on the other worker, and
writes a result file whose values are bit-identical to the serial sweep's; Ctrl-C on the
client exits 130 keeping its chunks, and ``--resume`` finishes to the same values."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from periodyn.engine.front import sweep_file
from periodyn.engine.threads import WORKER_THREAD_ENV
from periodyn.results import load
from periodyn.studies.spec import load_sweep_file
from tests.integration.datasets import pendulum_sweep_text, sigint_as_in_a_terminal, without_attrs

pytest.importorskip("distributed")

ROOT = Path(__file__).resolve().parents[2]
SPEEDS = 2000
CHUNK = 20
SWEEP = pendulum_sweep_text(SPEEDS, "sweep on a local Dask cluster, one of whose workers is killed by the test")
# Ctrl-C must land mid-sweep however fast the kernels run (a warm cache finishes 2,000 speeds
# in about a second): ten times longer, about 2 s of serial reference
CTRL_C_SPEEDS = 20000
CTRL_C_SWEEP = pendulum_sweep_text(CTRL_C_SPEEDS, "sweep on a local Dask cluster interrupted by Ctrl-C")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def environment() -> dict[str, str]:
    """The workers import periodyn from this checkout and run one thread per library."""
    env = dict(os.environ, **WORKER_THREAD_ENV)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), str(ROOT), env.get("PYTHONPATH", "")])
    return env


def _stderr(proc: subprocess.Popen) -> str:
    return proc.stderr.read().decode() if proc.stderr else Path(proc.log).read_text()


def _logged(command: list[str], log: Path) -> subprocess.Popen:
    """A cluster process whose stderr goes to the file ``log``: a scheduler logs a line per
    cancelled task, which fills an unread pipe and blocks it."""
    with open(log, "wb") as sink:
        proc = subprocess.Popen(command, env=environment(), stdout=subprocess.DEVNULL, stderr=sink)
    proc.log = log
    return proc


def wait_for(condition, what: str, seconds: float = 120.0, processes=()) -> None:
    deadline = time.monotonic() + seconds
    while not condition():
        for proc in processes:
            assert proc.poll() is None, f"{proc.args} ended early: {_stderr(proc)[-2000:]}"
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.02)


@pytest.fixture
def cluster(tmp_path):
    """(address, [worker processes]) of a scheduler and two one-thread workers without nannies
    (a nanny would restart a killed worker)."""
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    dask = [sys.executable, "-m", "dask"]
    started = [_logged(dask + ["scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                       tmp_path / "scheduler.log")]
    try:
        for name in ("a", "b"):
            started.append(_logged(dask + ["worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
                                           "--name", name, "--local-directory", str(tmp_path / f"worker-{name}")],
                                   tmp_path / f"worker-{name}.log"))
        from distributed import Client

        with Client(address, timeout="60s") as client:
            client.wait_for_workers(2, timeout=120)
        yield address, started[1:]
    finally:
        for proc in reversed(started):
            if proc.poll() is None:
                proc.terminate()
        for proc in reversed(started):
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()


def test_worker_killed_mid_sweep_result_equals_serial(cluster, tmp_path):
    address, workers = cluster
    sweep_path = tmp_path / "cluster.toml"
    sweep_path.write_text(SWEEP)
    out = tmp_path / "cluster.nc"
    parts = tmp_path / "cluster.nc.parts"
    run = subprocess.Popen([sys.executable, "-m", "periodyn.cli", "sweep", str(sweep_path), "--out", str(out),
                            "--scheduler", address, "--chunk-size", str(CHUNK), "--quiet"],
                           env=environment(), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        wait_for(lambda: len(list(parts.glob("chunk-*.npz"))) >= 4, "the first checkpointed chunks",
                 processes=[run, *workers])
        workers[0].send_signal(signal.SIGKILL)
        workers[0].wait()
        done_at_kill = len(list(parts.glob("chunk-*.npz")))
        assert done_at_kill < SPEEDS // CHUNK, "the sweep ended before the worker was killed; make it longer"
        _, stderr = run.communicate(timeout=300)
    finally:
        if run.poll() is None:
            run.kill()
            run.wait()
    assert run.returncode == 0, stderr.decode()[-3000:]
    assert workers[1].poll() is None
    clustered = load(out)
    assert clustered.attrs["backend"] == "dask" and clustered.attrs["points_computed"] == SPEEDS
    serial = sweep_file(load_sweep_file(sweep_path), progress=False)
    xr.testing.assert_identical(without_attrs(clustered), without_attrs(serial))


def test_chunks_are_split_for_a_cluster_with_more_threads_than_workers():
    from periodyn.engine.cluster import _for_cluster
    from periodyn.engine.options import ExecutionOptions

    chunks = [np.arange(0, 10), np.arange(10, 13), np.arange(13, 14)]
    split = _for_cluster(chunks, slots=8, workers=2, execution=ExecutionOptions())
    assert len(split) == 4 + 3 + 1 and np.array_equal(np.concatenate(split), np.arange(14))
    assert _for_cluster(chunks, slots=2, workers=2, execution=ExecutionOptions()) is chunks
    assert _for_cluster(chunks, slots=8, workers=2, execution=ExecutionOptions(chunk_size=10)) is chunks


def test_ctrl_c_on_a_cluster_sweep_exits_130_and_resumes_to_the_serial_result(cluster, tmp_path):
    """SIGINT to the client (Ctrl-C in its terminal) mid-sweep: exit 130 with the resume hint and
    no traceback, the finished chunks and the cluster kept, no lock left; ``--resume`` on the
    same cluster then gives the serial sweep's values."""
    from periodyn.engine.session import lock_path

    address, workers = cluster
    sweep_path = tmp_path / "cluster.toml"
    sweep_path.write_text(CTRL_C_SWEEP)
    out = tmp_path / "cluster.nc"
    parts = tmp_path / "cluster.nc.parts"
    command = [sys.executable, "-m", "periodyn.cli", "sweep", str(sweep_path), "--out", str(out),
               "--scheduler", address, "--chunk-size", str(CHUNK), "--quiet"]
    run = subprocess.Popen(command, env=environment(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           preexec_fn=sigint_as_in_a_terminal)
    try:
        wait_for(lambda: len(list(parts.glob("chunk-*.npz"))) >= 3, "the first checkpointed chunks",
                 processes=[run, *workers])
        run.send_signal(signal.SIGINT)
        _, stderr = run.communicate(timeout=120)
    finally:
        if run.poll() is None:
            run.kill()
            run.wait()
    err = stderr.decode()
    assert run.returncode == 130, err[-3000:]
    assert "interrupted; finished chunks are kept, continue with --resume" in err and "Traceback" not in err
    kept = len(list(parts.glob("chunk-*.npz")))
    assert 0 < kept < CTRL_C_SPEEDS // CHUNK and not out.exists() and not lock_path(out).exists()
    assert all(w.poll() is None for w in workers)  # the cluster outlives its client
    resumed = subprocess.run(command + ["--resume"], env=environment(), capture_output=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr.decode()[-3000:]
    clustered = load(out)
    assert clustered.attrs["points_computed"] < CTRL_C_SPEEDS  # the kept chunks were not computed again
    serial = sweep_file(load_sweep_file(sweep_path), progress=False)
    xr.testing.assert_identical(without_attrs(clustered), without_attrs(serial))
