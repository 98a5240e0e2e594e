"""Where a sweep's chunks are solved: in this process ("serial"), on a local pool of worker
processes ("processes", fork server where available) or on a Dask cluster ("dask").
Each backend yields finished chunks (result columns, see :meth:`Job.solve`) in any order.

Local worker processes start with one Numba/BLAS/OpenMP thread each (environment set
before they import numpy; Dask workers started by ``scheduler="local"`` too; on an
existing cluster the threads are limited when a worker receives its first chunk), and
the serial path limits the caller's process to one thread while it solves, so serial,
parallel and distributed results agree bit for bit. The job reaches each worker once.
"""

from __future__ import annotations

import hashlib
import multiprocessing
import os
import threading
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Iterator

import cloudpickle
import numpy as np

from ..errors import InputError
from .job import Job
from .threads import WORKER_THREAD_ENV, limit_threads, one_thread, worker_environment

__all__ = ["BACKENDS", "run_serial", "run_processes", "run_dask"]

_WORKER_JOB: Job | None = None
_DASK_JOBS: dict[str, Job] = {}


def _exit_with_parent() -> None:
    """End this worker when the sweep process dies (even by SIGKILL): a killed parent
    cannot shut the pool down, and its task queue never reports end-of-file."""
    parent = multiprocessing.parent_process()

    def watch():
        parent.join()
        os._exit(1)

    threading.Thread(target=watch, name="periodyn-parent-watch", daemon=True).start()


def _init_worker(payload: bytes) -> None:
    global _WORKER_JOB
    _exit_with_parent()
    limit_threads()
    _WORKER_JOB = cloudpickle.loads(payload)


def _solve_in_worker(indices: np.ndarray) -> dict[str, np.ndarray]:
    return _WORKER_JOB.solve(indices)


def _solve_on_dask_worker(payload: bytes, token: str, indices: np.ndarray) -> dict[str, np.ndarray]:
    job = _DASK_JOBS.get(token)
    if job is None:
        limit_threads()
        job = _DASK_JOBS.setdefault(token, cloudpickle.loads(payload))
    return job.solve(indices)



def run_serial(job: Job, chunks: list[np.ndarray], workers: int, scheduler) -> Iterator[dict]:
    with one_thread():  # for the whole run: entering costs a scan of the loaded libraries
        for chunk in chunks:
            yield job.solve(chunk)


def _process_context():
    """Start method for local workers: "forkserver" where available (a server process
    imports periodyn and loads the speed solver's compiled kernels once, in the
    one-thread environment of its first start, and forks the workers, so pools after the
    first start in milliseconds), else "spawn"."""
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload([__name__, "periodyn._forkserver_preload"])
    return context


def run_processes(job: Job, chunks: list[np.ndarray], workers: int, scheduler) -> Iterator[dict]:
    payload = cloudpickle.dumps(job)
    with worker_environment():
        pool = ProcessPoolExecutor(max_workers=workers, mp_context=_process_context(),
                                   initializer=_init_worker, initargs=(payload,))
        try:
            futures = [pool.submit(_solve_in_worker, chunk) for chunk in chunks]
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise
    try:
        for future in as_completed(futures):
            yield future.result()
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _dask_client(scheduler, workers: int):
    """(client, things to close): an existing Client, 'local' (a LocalCluster with
    ``workers`` one-thread processes) or a scheduler address."""
    import dask
    from distributed import Client, LocalCluster

    if isinstance(scheduler, Client):
        return scheduler, []
    if scheduler == "local":
        with dask.config.set({"distributed.nanny.pre-spawn-environ": WORKER_THREAD_ENV}):
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
        client = Client(cluster)
        return client, [client, cluster]
    try:
        client = Client(scheduler, timeout="10s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"cannot connect to the Dask scheduler at {scheduler!r} ({exc}); check the address "
                         "(tcp://host:8786) and that the scheduler is running") from None
    return client, [client]


def run_dask(job: Job, chunks: list[np.ndarray], workers: int, scheduler) -> Iterator[dict]:
    from distributed import as_completed as dask_as_completed

    client, owned = _dask_client(scheduler, workers)
    futures = []
    try:
        payload = cloudpickle.dumps(job)
        token = hashlib.sha256(payload).hexdigest()
        shared = client.scatter(payload, broadcast=True)
        futures = [client.submit(_solve_on_dask_worker, shared, token, chunk, pure=False) for chunk in chunks]
        for future in dask_as_completed(futures):
            yield future.result()
    finally:
        if futures:
            client.cancel(futures)
        for thing in owned:
            thing.close()



BACKENDS = {"serial": run_serial, "processes": run_processes, "dask": run_dask}
