"""A sweep's output cannot be mixed, damaged silently or written somewhere it cannot be:
one sweep at a time on an ``--out`` (a lock, taken over from a killed holder), checkpoint
chunks of another sweep never merged, result files checksummed, the output path checked
before any computing, OS errors and Ctrl-C ending with a message and exit 2 / 130."""

from __future__ import annotations

import errno
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import h5py
import numpy as np
import pytest
import xarray as xr

from periodyn.cli import main
from periodyn.engine import job as job_module
from periodyn.engine.front import ExecutionOptions, sweep
from periodyn.engine.session import lock_path
from periodyn.errors import InputError
from periodyn.examples import pendulum
from periodyn.results import load
from tests.integration.datasets import sigint_as_in_a_terminal, without_attrs

W0 = np.sqrt(9.81)
OMEGA_A = W0 * np.linspace(0.2, 1.3, 20)
OMEGA_B = W0 * np.linspace(0.25, 1.35, 20)  # another --omega: same chunk names, other speeds
M = 5
CHUNK = ExecutionOptions(chunk_size=5)
SRC = str(Path(__file__).resolve().parents[2] / "src")

TINY = """
description = "tiny pendulum sweep"
[model]
example = "pendulum"
[sweep]
omega = { start = 0.3, stop = 1.2, num = 12, unit = "omega0" }
harmonics = 4
samples = 24
"""


@pytest.fixture(scope="module")
def model():
    return pendulum(samples=24)


@pytest.fixture(scope="module")
def clean_a(model):
    return without_attrs(sweep(model, OMEGA_A, M, progress=False))


def interrupted(model, omega, out: Path, points: int) -> None:
    """Run a sweep into ``out`` and stop it once ``points`` points are checkpointed."""
    def stop(done, total):
        if done >= points:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sweep(model, omega, M, out=out, execution=CHUNK, progress=stop)


# ----------------------------------------------------------------------------- mixing
def test_chunks_of_another_sweep_are_dropped_and_recomputed(model, clean_a, tmp_path):
    """Two sweeps with different speeds wrote into one parts folder (as when started together
    on one --out): resuming the first gives exactly its clean result, never a mix."""
    out_a, out_b = tmp_path / "a.nc", tmp_path / "b.nc"
    interrupted(model, OMEGA_A, out_a, 5)
    interrupted(model, OMEGA_B, out_b, 15)
    parts_a = out_a.with_name("a.nc.parts")
    for chunk in out_b.with_name("b.nc.parts").glob("chunk-*.npz"):
        shutil.copy(chunk, parts_a / chunk.name)  # the other sweep's chunks, one over a chunk of A
    with pytest.warns(UserWarning, match="belongs to another sweep"):
        resumed = sweep(model, OMEGA_A, M, out=out_a, execution=CHUNK, resume=True, progress=False)
    xr.testing.assert_identical(without_attrs(resumed), clean_a)
    xr.testing.assert_identical(without_attrs(load(out_a)), clean_a)


def test_a_chunk_at_other_points_is_dropped(model, clean_a, tmp_path):
    """A chunk of this sweep whose index was changed (points it does not hold) is recomputed."""
    out = tmp_path / "s.nc"
    interrupted(model, OMEGA_A, out, 5)
    parts = out.with_name("s.nc.parts")
    (path,) = parts.glob("chunk-*.npz")
    with np.load(path) as data:
        chunk = {k: data[k] for k in data.files}
    np.savez(parts / "chunk-0000000005-5.npz", **{**chunk, "index": chunk["index"] + 5})
    np.savez(parts / "chunk-0000000100-5.npz", **{**chunk, "index": chunk["index"] + 100})
    with pytest.warns(UserWarning) as caught:
        resumed = sweep(model, OMEGA_A, M, out=out, execution=CHUNK, resume=True, progress=False)
    assert sorted(str(w.message).split(" holds ")[1].split(";")[0] for w in caught) == [
        "point indices outside this sweep", "points at other values of omega than this sweep's"]
    xr.testing.assert_identical(without_attrs(resumed), clean_a)


def test_a_chunk_without_a_fingerprint_is_not_used(model, clean_a, tmp_path):
    out = tmp_path / "s.nc"
    interrupted(model, OMEGA_A, out, 5)
    (path,) = out.with_name("s.nc.parts").glob("chunk-*.npz")
    with np.load(path) as data:
        chunk = {k: data[k] for k in data.files if not k.startswith("_")}
    chunk["amplitude"] = chunk["amplitude"] * 2
    np.savez(path, **chunk)
    with pytest.warns(UserWarning, match="no sweep fingerprint"):
        resumed = sweep(model, OMEGA_A, M, out=out, execution=CHUNK, resume=True, progress=False)
    xr.testing.assert_identical(without_attrs(resumed), clean_a)


# ----------------------------------------------------------------------------- lock
def hold_lock(out: Path) -> subprocess.Popen:
    """Another process holding the sweep lock on ``out`` (as a running sweep does)."""
    code = textwrap.dedent(f"""
        import sys, time
        from periodyn.engine.session import sweep_guard
        with sweep_guard({str(out)!r}):
            print("held", flush=True)
            time.sleep(120)
        """)
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True,
                            env={**os.environ, "PYTHONPATH": SRC})
    assert proc.stdout.readline().strip() == "held"
    return proc


def test_second_sweep_on_one_out_is_refused_and_a_dead_holder_taken_over(model, clean_a, tmp_path, capsys):
    out = tmp_path / "s.nc"
    holder = hold_lock(out)
    try:
        with pytest.raises(InputError, match=f"another sweep is writing {out} \\(pid {holder.pid} on .*, started "):
            sweep(model, OMEGA_A, M, out=out, progress=False)
        (tmp_path / "sweeps").mkdir()
        (tmp_path / "sweeps" / "tiny.toml").write_text(TINY)
        assert main(["sweep", str(tmp_path / "sweeps" / "tiny.toml"), "--out", str(out), "--workers", "1"]) == 2
        assert f"pid {holder.pid}" in capsys.readouterr().err
        assert not out.exists() and not out.with_name("s.nc.parts").exists()
    finally:
        holder.kill()
        holder.wait()
    assert lock_path(out).exists()  # SIGKILL left the lock file: its lock died with the process
    ds = sweep(model, OMEGA_A, M, out=out, progress=False)
    xr.testing.assert_identical(without_attrs(ds), clean_a)
    assert not lock_path(out).exists()


# ----------------------------------------------------------------------------- checksums
def flip(path: Path, variable: str) -> None:
    """Invert up to 4 KiB of the stored bytes of ``variable`` (its first chunk)."""
    with h5py.File(path, "r") as f:
        info = f[variable].id.get_chunk_info(0)
    offset, size = info.byte_offset, min(info.size, 4096)
    data = bytearray(path.read_bytes())
    data[offset:offset + size] = bytes(b ^ 0xFF for b in data[offset:offset + size])
    path.write_bytes(bytes(data))


@pytest.mark.parametrize("variable", ["harmonics", "message", "omega"])
def test_flipped_bytes_are_a_read_error_and_never_resumed(model, tmp_path, capsys, variable):
    (tmp_path / "tiny.toml").write_text(TINY)
    out = tmp_path / "r.nc"
    assert main(["sweep", str(tmp_path / "tiny.toml"), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    load(out)
    flip(out, variable)
    with pytest.raises(InputError, match=f"{out} is not a readable periodyn result file, or it is damaged"):
        load(out)
    assert main(["sweep", str(tmp_path / "tiny.toml"), "--out", str(out), "--workers", "1", "--resume"]) == 2
    err = capsys.readouterr().err
    assert "damaged" in err and str(out) in err and "Traceback" not in err


# ----------------------------------------------------------------------------- paths and OS errors
@pytest.fixture
def project(tmp_path, monkeypatch):
    (tmp_path / "tiny.toml").write_text(TINY)
    monkeypatch.chdir(tmp_path)

    def never(*args, **kwargs):
        pytest.fail("a point was computed before the output path was checked")

    monkeypatch.setattr(job_module.Job, "solve", never)
    return tmp_path


@pytest.mark.parametrize("make, out, message", [
    (lambda p: (p / "folder.nc").mkdir(), "folder.nc", "--out folder.nc is a folder; give a file path such as"),
    (lambda p: (p / "file").write_text("x"), "file/r.nc", "--out file/r.nc lies below file, which is a file"),
    (lambda p: (p / "file").write_text("x"), "file/deeper/r.nc", "lies below file, which is a file"),
])
def test_unusable_out_is_refused_before_computing(project, capsys, make, out, message):
    make(project)
    assert main(["sweep", "tiny.toml", "--out", out, "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_unusable_plot_path_is_refused_before_computing(project, capsys):
    (project / "pic.png").mkdir()
    assert main(["sweep", "tiny.toml", "--out", "r.nc", "--plot", "pic.png", "--workers", "1"]) == 2
    assert "--plot pic.png is a folder" in capsys.readouterr().err


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_read_only_folder_is_refused_before_computing(project, capsys):
    (project / "ro").mkdir(mode=0o555)
    assert main(["sweep", "tiny.toml", "--out", "ro/r.nc", "--workers", "1"]) == 2
    assert "the folder ro of --out ro/r.nc is not writable" in capsys.readouterr().err


def test_unwritable_folder_is_refused_before_computing(project, capsys, monkeypatch):
    """(As root every folder is writable: the folder's answer to os.access stands in.)"""
    real = os.access
    monkeypatch.setattr(os, "access", lambda path, mode: Path(path).name != "ro" and real(path, mode))
    (project / "ro").mkdir()
    assert main(["sweep", "tiny.toml", "--out", "ro/r.nc", "--workers", "1"]) == 2
    assert "the folder ro of --out ro/r.nc is not writable; make it writable" in capsys.readouterr().err


@pytest.mark.parametrize("where", ["chunk", "result"])
def test_full_disk_exits_2_naming_the_path(tmp_path, monkeypatch, capsys, where):
    (tmp_path / "tiny.toml").write_text(TINY)
    monkeypatch.chdir(tmp_path)

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    if where == "chunk":
        monkeypatch.setattr("periodyn.engine.checkpoint.np.savez", full)
    else:
        monkeypatch.setattr(xr.Dataset, "to_netcdf", full)
    assert main(["sweep", "tiny.toml", "--out", "r.nc", "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert "No space left on device" in err and "free space" in err and "Traceback" not in err
    assert ("r.nc.parts/chunk-" if where == "chunk" else "result file r.nc") in err
    assert not list(tmp_path.glob("*.partial")) and not lock_path(tmp_path / "r.nc").exists()


# ----------------------------------------------------------------------------- Ctrl-C
INTERRUPT_SWEEP = """
description = "sweep that the test interrupts"
[model]
example = "pendulum"
[sweep]
omega = { start = 0.05, stop = 1.4, num = 100000, unit = "omega0" }
harmonics = 10
samples = 48
"""


def descendants(pid: int) -> list[int]:
    path = Path(f"/proc/{pid}/task/{pid}/children")
    kids = [int(c) for c in path.read_text().split()] if path.exists() else []
    return kids + [d for k in kids for d in descendants(k)]


@pytest.mark.parametrize("workers, delay", [(1, 0.37), (2, 0.5), (2, 1.5)])
def test_ctrl_c_exits_130_with_the_resume_hint(tmp_path, workers, delay):
    """SIGINT to the sweep's process group (what a terminal's Ctrl-C sends) at several
    moments once chunks are checkpointed (and the workers run compiled kernels): exit 130,
    the message, no traceback (a worker hit inside a Numba kernel used to fail the sweep
    with "SystemError ... returned a result with an exception set"), the chunks kept, no
    process left."""
    (tmp_path / "i.toml").write_text(INTERRUPT_SWEEP)
    out = tmp_path / "i.nc"
    parts = tmp_path / "i.nc.parts"
    proc = subprocess.Popen([sys.executable, "-m", "periodyn.cli", "sweep", str(tmp_path / "i.toml"), "--out",
                             str(out), "--workers", str(workers), "--chunk-size", "50", "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            env={**os.environ, "PYTHONPATH": SRC}, preexec_fn=sigint_as_in_a_terminal)
    deadline = time.monotonic() + 120
    # with workers: the two workers forked from the sweep's process (from a fork server: the
    # server, the resource tracker and a worker)
    while len(list(parts.glob("chunk-*.npz"))) < 3 or len(descendants(proc.pid)) < (2 if workers > 1 else 0):
        assert proc.poll() is None, proc.stderr.read()
        assert time.monotonic() < deadline, "the sweep wrote no checkpoint or started no worker"
        time.sleep(0.005)
    time.sleep(delay)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "interrupted; finished chunks are kept, continue with --resume" in err and "Traceback" not in err
    assert "stopping after the current chunk" in err
    assert list(parts.glob("chunk-*.npz")) and not out.exists() and not lock_path(out).exists()
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:  # the workers (and a fork server) end with the sweep
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            return
        time.sleep(0.05)
    pytest.fail("processes of the interrupted sweep are still running")


def test_an_interrupt_inside_a_c_call_is_an_interrupt(monkeypatch, capsys):
    """Ctrl-C landing inside a compiled function surfaces as a SystemError caused by the
    KeyboardInterrupt: still exit 130 and the message, no traceback."""
    import periodyn.cli as cli

    def hit(args):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise SystemError("CPUDispatcher(<function ladder_climb>) returned a result with an exception set") \
                from exc

    monkeypatch.setattr(cli, "_cmd_sweep", hit)
    monkeypatch.setitem(cli._COMMANDS, "sweep", hit)
    assert main(["sweep", "any.toml"]) == 130
    assert capsys.readouterr().err == "periodyn sweep: interrupted; finished chunks are kept, continue with --resume\n"


def test_a_worker_cut_off_while_starting_ends_without_a_traceback(capsys, monkeypatch):
    """The fork server's hook: a worker whose start data were cut off (the sweep stopped
    while handing them over) says nothing; any other failure is printed as before."""
    import pickle

    monkeypatch.setattr(sys, "excepthook", sys.excepthook)  # importing the module sets it in this process
    from periodyn.engine import _forkserver_preload as preload

    for kind in (pickle.UnpicklingError, EOFError):
        preload._quiet_when_the_sweep_stopped(kind, kind("pickle data was truncated"), None)
    assert capsys.readouterr().err == ""
    preload._quiet_when_the_sweep_stopped(ValueError, ValueError("a real failure"), None)
    assert "a real failure" in capsys.readouterr().err
