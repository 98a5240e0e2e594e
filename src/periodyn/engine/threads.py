"""Threads and cores: one BLAS/OpenMP and one Numba thread per sweep process, on every
path (serial in the caller's process, local worker processes, Dask workers), so every
point is computed by the same single-threaded code whatever the backend and the results
agree bit for bit (the limits themselves: :mod:`periodyn.numerics.threads`). Light on
purpose: imports only the standard library at module level."""

from __future__ import annotations

import contextlib
import os
import sys
from typing import Iterator

__all__ = ["WORKER_THREAD_ENV", "AUTO_PARALLEL_POINTS", "available_cores", "auto_workers", "worker_environment"]

#: Environment of worker processes: one thread per library, set before numpy is imported.
WORKER_THREAD_ENV = {
    "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
    "VECLIB_MAXIMUM_THREADS": "1", "NUMEXPR_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1",
}


def available_cores() -> int:
    """CPU cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


#: Sweeps with fewer points run in one process under ``workers="auto"``: starting a
#: worker process (imports, first point) costs about a second.
AUTO_PARALLEL_POINTS = 2000


def auto_workers(points: int) -> int:
    """Worker processes for a sweep of ``points`` points: all cores from
    AUTO_PARALLEL_POINTS on, else 1."""
    return available_cores() if points >= AUTO_PARALLEL_POINTS else 1


@contextlib.contextmanager
def worker_environment() -> Iterator[None]:
    """Start processes inside the block with the one-thread environment and without
    re-running the caller's script: the job reaches workers by cloudpickle, so a script
    lacking an ``if __name__ == "__main__"`` guard must not be executed again in them
    (with spawn and forkserver, multiprocessing re-imports ``__main__`` from its
    ``__file__`` in every child). NUMBA_NUM_THREADS stays as it is here: Numba re-reads
    it in this process whenever a module with jitted functions is imported, and refuses
    a value other than the one its thread pool was launched with; the workers call
    :func:`limit_threads` instead."""
    env = {k: v for k, v in WORKER_THREAD_ENV.items() if k != "NUMBA_NUM_THREADS"}
    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    main = sys.modules["__main__"]
    main_file = main.__dict__.pop("__file__", None) if getattr(main, "__spec__", None) is None else None
    try:
        yield
    finally:
        if main_file is not None:
            main.__file__ = main_file
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v

