"""What runs inside a local worker process of a sweep (:mod:`periodyn.engine.backends`):
its start (the job, one thread per library, Ctrl-C left to the sweep's process, an end
with the sweep's process) and the solve of one chunk."""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading

import cloudpickle
import numpy as np

from .job import Job
from .session import forget_locks
from .stream import receipt
from ..numerics.threads import limit_threads

__all__ = ["init_worker", "solve_in_worker", "ready"]

_WORKER_JOB: Job | None = None


def _exit_with_parent() -> None:
    """End this worker when the sweep process dies (even by SIGKILL): a killed parent
    cannot shut the pool down, and its task queue never reports end-of-file."""
    parent = multiprocessing.parent_process()

    def watch():
        parent.join()
        os._exit(1)

    threading.Thread(target=watch, name="periodyn-parent-watch", daemon=True).start()


def init_worker(job: Job | bytes) -> None:
    """Start of a worker: ``job`` as the object itself (a worker forked from the sweep's
    process, which holds it) or cloudpickled (a worker from the fork server or spawned).
    A forked worker also closes its copy of the sweep's lock on ``out``
    (:func:`periodyn.engine.session.forget_locks`): after a SIGKILL of the sweep, a
    worker that has not ended yet must not hold it against the ``--resume``."""
    global _WORKER_JOB
    forget_locks()
    _exit_with_parent()
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C reaches the whole group: the sweep's process decides
    limit_threads()
    _WORKER_JOB = cloudpickle.loads(job) if isinstance(job, bytes) else job


def solve_in_worker(indices: np.ndarray) -> dict[str, np.ndarray]:
    """The chunk's results; with ``job.writer`` (the sweep's checkpoint) written here first and
    marked ``written``, or only a receipt of them where the results stream (``job.streamed``).
    The results come back rather than being read back from the checkpoint file: unpickling a
    chunk and storing its columns costs the sweep's process about 0.15 ms, reading its file 6 ms."""
    chunk = _WORKER_JOB.solve(indices)
    if _WORKER_JOB.writer is None:
        return chunk
    _WORKER_JOB.writer.write(chunk)
    return receipt(chunk) if _WORKER_JOB.streamed else {"written": np.True_, **chunk}


def ready() -> None:
    """A task that returns once a worker has started (imports, job loaded)."""
