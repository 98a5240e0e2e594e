"""The Dask backend of a sweep (:mod:`periodyn.engine.backends` has the others): an existing
cluster (a scheduler address or a ``Client``) or a local one (``scheduler="local"``). The job
reaches each worker once (scattered), each worker limits itself to one thread when it
receives its first chunk, so results are bit-identical to a serial sweep. A worker lost
mid-sweep costs only its chunks (the scheduler runs them again elsewhere), a collected chunk
is released on its worker at once, and the chunks are split further for a cluster with more
threads than ``workers``. Dask and distributed are imported only here, when used.
"""

from __future__ import annotations

import hashlib
import os
from typing import Iterator

import cloudpickle
import numpy as np

from ..errors import InputError
from .job import Job
from .options import ExecutionOptions
from ..numerics.threads import limit_threads
from .threads import WORKER_THREAD_ENV

__all__ = ["run_dask"]

_DASK_JOBS: dict[str, Job] = {}


def _solve_on_dask_worker(payload: bytes, token: str, indices: np.ndarray) -> dict[str, np.ndarray]:
    job = _DASK_JOBS.get(token)
    if job is None:
        limit_threads()
        job = _DASK_JOBS.setdefault(token, cloudpickle.loads(payload))
    return job.solve(indices)


def _dask_client(scheduler, workers: int):
    """(client, things to close): an existing Client, 'local' (a LocalCluster with
    ``workers`` one-thread processes) or a scheduler address."""
    import dask
    from distributed import Client, LocalCluster

    if isinstance(scheduler, Client):
        return scheduler, []
    if scheduler == "local":
        # the nanny writes its pre-spawn environment into this process's os.environ for good:
        # restore it, or Numba here would later re-read NUMBA_NUM_THREADS and refuse a change
        saved = dict(os.environ)
        try:
            with dask.config.set({"distributed.nanny.pre-spawn-environ": WORKER_THREAD_ENV}):
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
        finally:
            os.environ.clear()
            os.environ.update(saved)
        client = Client(cluster)
        return client, [client, cluster]
    try:
        client = Client(scheduler, timeout="10s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"cannot connect to the Dask scheduler at {scheduler!r} ({exc}); check the address "
                         "(tcp://host:8786) and that the scheduler is running") from None
    return client, [client]


def _for_cluster(chunks: list[np.ndarray], slots: int, workers: int, execution: ExecutionOptions) -> list:
    """The chunks (made for ``workers``) split further for a cluster of ``slots`` worker
    threads, so each still gets several; an explicit ``chunk_size`` is kept."""
    if execution.chunk_size or slots <= workers:
        return chunks
    pieces = -(-slots // max(workers, 1))
    return [piece for chunk in chunks for piece in np.array_split(chunk, min(pieces, len(chunk)))]


def run_dask(job: Job, chunks: list[np.ndarray], workers: int, execution: ExecutionOptions) -> Iterator[dict]:
    from distributed import as_completed as dask_as_completed

    client, owned = _dask_client(execution.scheduler, workers)
    left: set = set()  # futures not yet collected: a collected chunk is released on its worker at once
    try:
        chunks = _for_cluster(chunks, sum(client.nthreads().values()), workers, execution)
        payload = cloudpickle.dumps(job)
        token = hashlib.sha256(payload).hexdigest()
        shared = client.scatter(payload, broadcast=True)
        left.update(client.submit(_solve_on_dask_worker, shared, token, chunk, pure=False) for chunk in chunks)
        for future in dask_as_completed(list(left)):
            result = future.result()
            left.discard(future)
            del future
            yield result
    finally:
        if left:
            client.cancel(list(left))
        for thing in owned:
            thing.close()
