"""How local worker processes start: forked from the sweep's process where that is safe,
else from a fork server: the same results bit for bit either way; forking refused while
another thread runs (a lock it holds would stay locked in the child), the sweep then going
on with the fork server; a forked worker not holding the sweep's lock on ``out``."""

from __future__ import annotations

import fcntl
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from periodyn.engine import backends, pools, session
from periodyn.engine.front import ExecutionOptions, sweep
from periodyn.errors import InputError
from periodyn.examples import pendulum
from tests.integration.datasets import without_attrs

OMEGA = np.sqrt(9.81) * np.linspace(0.2, 1.3, 16)
EAGER = {"chunk_size": 3, "eager_workers": True}


def pools_made() -> list[str]:
    """Records the kind of every pool the sweeps of this process start."""
    made = []
    for kind in ("ForkedPool", "FedPool"):
        original = getattr(backends, kind)

        def record(*args, _original=original, _kind=kind, **kwargs):
            made.append(_kind)
            return _original(*args, **kwargs)

        setattr(backends, kind, record)
    return made


def in_fresh_interpreter(body: str) -> None:
    """Run this module's function ``body`` in a new interpreter: whether a fork is allowed
    depends on the threads of the whole process, and earlier tests in this one leave some
    (Dask's, the fork server's start threads while it loads)."""
    root = Path(__file__).resolve().parents[2]
    run = subprocess.run([sys.executable, "-c", f"from tests.integration.test_worker_start import {body}; {body}()"],
                         cwd=root, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr


def forked_and_served() -> None:
    made = pools_made()
    model = pendulum(samples=24)
    serial = sweep(model, OMEGA, 4, progress=False)
    assert pools.fork_problem() == ""  # a fresh process runs no other thread
    forked = sweep(model, OMEGA, 4, workers=2, execution=ExecutionOptions(**EAGER), progress=True)
    assert pools.fork_problem() == ""  # nor after a forked sweep with a progress bar
    served = sweep(model, OMEGA, 4, workers=2, progress=False,
                   execution=ExecutionOptions(**EAGER, worker_start="forkserver"))
    assert made == ["ForkedPool", "FedPool"], made
    for parallel in (forked, served):
        assert parallel.attrs["backend"] == "processes"
        xr.testing.assert_identical(without_attrs(parallel), without_attrs(serial))


def no_fork_while_another_thread_runs() -> None:
    made = pools_made()
    stop = threading.Event()
    other = threading.Thread(target=stop.wait, daemon=True)
    other.start()
    try:
        assert "other Python threads" in pools.fork_problem()
        ds = sweep(pendulum(samples=24), OMEGA, 4, workers=2, execution=ExecutionOptions(**EAGER), progress=False)
    finally:
        stop.set()
        other.join()
    assert made == ["FedPool"] and ds.attrs["backend"] == "processes", made
    deadline = time.monotonic() + 120  # a pool closed while its workers were starting stops once they are up
    while threading.active_count() > 1 and time.monotonic() < deadline:
        for thread in threading.enumerate():
            if thread is not threading.main_thread():
                thread.join(1.0)
    assert pools.fork_problem() == ""


def test_forked_and_fork_server_workers_equal_the_serial_sweep():
    in_fresh_interpreter("forked_and_served")


def test_no_fork_while_another_thread_runs():
    in_fresh_interpreter("no_fork_while_another_thread_runs")


@pytest.mark.parametrize("forget", [True, False])
def test_a_forked_process_drops_its_copy_of_the_sweeps_lock(tmp_path, forget):
    """The lock on ``out`` stays with the sweep's process: once that lets it go, a forked
    child that closed its copy (:func:`session.forget_locks`, as a worker does) no longer
    holds it; one that kept its copy still would (the control)."""
    out = tmp_path / "r.nc"
    with session.sweep_guard(out):
        probe = os.open(session.lock_path(out), os.O_RDWR)  # the same file, another open file description
        ready, told = os.pipe()
        pid = os.fork()
        if pid == 0:  # the child: drop the copy (or not), say so, then outlive the sweep's lock
            try:
                if forget:
                    session.forget_locks()
                os.write(told, b"x")
                threading.Event().wait(10.0)
            finally:
                os._exit(0)
        os.read(ready, 1)
    try:
        if forget:
            fcntl.flock(probe, fcntl.LOCK_EX | fcntl.LOCK_NB)  # free although the child still lives
        else:
            with pytest.raises(BlockingIOError):
                fcntl.flock(probe, fcntl.LOCK_EX | fcntl.LOCK_NB)
    finally:
        os.kill(pid, 9)
        os.waitpid(pid, 0)
        for fd in (probe, ready, told):
            os.close(fd)


def test_worker_start_is_checked():
    with pytest.raises(InputError, match="worker_start must be one of 'auto', 'forkserver', 'spawn'"):
        ExecutionOptions(worker_start="thread")
