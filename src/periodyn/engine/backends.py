"""Where a sweep's chunks are solved: in this process ("serial"), on local worker
processes ("processes") or on a Dask cluster ("dask", :mod:`periodyn.engine.cluster`).
Each backend yields finished chunks (result columns, see :meth:`Job.solve`) in any order.

Local workers (:mod:`periodyn.engine.pools`) are forked from this process once the model
is built, where that is safe (:func:`~periodyn.engine.pools.fork_problem`): they hold the
job, the built models and the loaded kernels, are up in milliseconds, and this process
only collects. Elsewhere they come from a fork server (or are spawned), and this process
solves chunks until the first of them is up (a short sweep never waits for them), then
only collects. Either way each worker writes its chunks' checkpoint files where it
solves them (``job.writer``) and sends back the chunk (a receipt where results stream),
so the calling process only stores what comes back (a few array copies per chunk).

Local workers run one Numba/BLAS/OpenMP thread each (:func:`~periodyn.numerics.threads.limit_threads`;
those from a fork server also start in the one-thread environment; Dask workers started
by ``scheduler="local"`` too; on an existing cluster the threads are limited when a
worker receives its first chunk), and the serial path limits the caller's process to one
thread while it solves, so serial, parallel and distributed results agree bit for bit.
Local workers ignore Ctrl-C: the sweep's process stops between chunks
(:mod:`periodyn.engine.session`) and shuts them down.
"""

from __future__ import annotations

import atexit
import contextlib
import os
import signal
import time
from typing import Iterable, Iterator

import numpy as np

from .cluster import run_dask
from .job import Job
from .options import ExecutionOptions
from .pools import FedPool, ForkedPool, fork_problem, process_context, sigint_ignored
from ..numerics.threads import one_thread
from .threads import worker_environment

__all__ = ["BACKENDS", "run_serial", "run_processes", "start_server_early"]


def run_serial(job: Job, chunks: list[np.ndarray], workers: int, execution: ExecutionOptions) -> Iterator[dict]:
    with one_thread():  # for the whole run: entering costs a scan of the loaded libraries
        for chunk in chunks:
            yield job.solve(chunk)


#: Seconds that starting local workers costs this process: the wait until the first worker
#: is up plus the pool's shutdown. The first pool from the fork server starts the server,
#: which imports periodyn and loads the compiled kernels; later pools fork from it. Workers
#: forked from this process ("fork") are up in milliseconds. The values are priors until a
#: pool of this process has been timed, then the latest measurement.
START_COST = {"first": 2.0, "later": 0.2, "fork": 0.05}
#: Measured chunk times were 0.8-2.9 times their estimate (:meth:`periodyn.speeds.SpeedSolver.speed_costs`):
#: workers start without timing chunks first where they pay even at this fraction of the estimate.
ESTIMATE_LOW = 0.5
_STARTED: list[bool] = []  # a pool was started from the fork server of this process
_SERVER_SINCE: list[float] = []  # when this process started the fork server ahead of its first pool


def _forking(execution: ExecutionOptions | None) -> bool:
    """Whether workers started now would be forked from this process."""
    return (execution is None or execution.worker_start == "auto") and not fork_problem()


def start_server_early(execution: ExecutionOptions | None = None) -> None:
    """Start the fork server (imports and kernel loading, :func:`process_context`) before
    the first pool of this process, so that it warms up on another core while this
    process builds the model and solves its first chunks; nothing where the workers would
    be forked from this process (:func:`_forking`), with the "spawn" start method, or once
    started. A server no pool used is stopped when this process exits: it holds this
    process's output pipes and would keep a caller reading them waiting until its warm-up ends."""
    method = execution.worker_start if execution is not None else "auto"
    context = process_context(method)
    if _STARTED or _SERVER_SINCE or context.get_start_method() != "forkserver" or _forking(execution):
        return
    from multiprocessing import forkserver

    _ensure_server(method)
    _SERVER_SINCE.append(time.perf_counter())
    pid = getattr(forkserver._forkserver, "_forkserver_pid", None)
    if pid is not None:
        atexit.register(_stop_unused_server, pid)


def _ensure_server(method: str) -> None:
    """Start the fork server (and the resource tracker) from this thread, with one thread
    per process and SIGINT ignored, where workers are forked from one."""
    if process_context(method).get_start_method() == "forkserver":
        from multiprocessing import forkserver

        with worker_environment(), sigint_ignored():
            forkserver.ensure_running()


def _stop_unused_server(pid: int) -> None:
    if not _STARTED:
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGTERM)


def _start_cost(execution: ExecutionOptions | None = None) -> float:
    """Expected seconds until a worker is up: START_COST "fork" where the workers would be
    forked from this process; from the fork server "later" after its first pool; for the
    first, "first" less the time the fork server has already had (at least "later")."""
    if _forking(execution):
        return START_COST["fork"]
    if _STARTED:
        return START_COST["later"]
    if _SERVER_SINCE:
        return max(START_COST["later"], START_COST["first"] - (time.perf_counter() - _SERVER_SINCE[0]))
    return START_COST["first"]


def _worth_starting(left: float, chunk_seconds: float, workers: int, execution: ExecutionOptions | None = None) -> bool:
    """Whether ``workers`` worker processes would finish the chunks left (``left``
    estimated seconds, chunks of about ``chunk_seconds``) sooner than this process alone.
    This process keeps solving while they start (:data:`START_COST`); the work left then
    is shared by the ``workers`` processes, which saves ``(left - start) (1 - 1/workers)``;
    that must exceed the expected wait for the last chunk sent to a worker (half a chunk)."""
    return (left - _start_cost(execution)) * (1.0 - 1.0 / workers) > 0.5 * chunk_seconds


def _record_start(pool, closed: float) -> None:
    """Store the measured start (until a worker was up, plus ``closed`` s of shutdown) of a
    forked pool as ``START_COST["fork"]``, of a pool from the fork server after its first
    as ``START_COST["later"]``."""
    if getattr(pool, "forked", False):
        if pool.ready_after is not None:
            START_COST["fork"] = pool.ready_after + closed
        return
    if _STARTED and pool.ready_after is not None:
        START_COST["later"] = pool.ready_after + closed
    elif _STARTED:  # closed before a worker was up: its start took at least that long
        START_COST["later"] = max(START_COST["later"], time.perf_counter() - pool.created)
    if pool.ready_after is not None:  # a worker came up: the fork server is ready for the next pools
        _STARTED.append(True)


def run_processes(job: Job, chunks: list[np.ndarray], workers: int, execution: ExecutionOptions) -> Iterable[dict]:
    """``workers`` local worker processes. Where the chunks' estimated costs
    (:meth:`Job.point_costs`) make the workers pay even at :data:`ESTIMATE_LOW` times the
    estimate (:func:`_worth_starting`), they start at once (``execution.eager_workers``:
    whatever the estimate): forked from this process where safe, here, before the caller
    starts any thread (a progress bar's), so this function starts them when called, not
    when iterated. Otherwise this process (one thread, as the serial path) solves
    the last two chunks first and times the second; the rest is estimated from that time
    scaled by the chunks' estimated costs (at low speeds a chunk may cost many times the
    last one), and unless the workers would finish the rest sooner, counting their
    start, it solves them alone. Workers from the fork server take chunks from the front
    while this process solves chunks from the back until the first worker is up, so a
    short sweep never waits for them; from then on it only collects what they finish.
    The fork server of the first pool starts at once where the chunks are estimated to
    take longer than its start (:func:`start_server_early`)."""
    costs = [float(job.point_costs(c).sum()) for c in chunks]  # estimated seconds per chunk
    at_once = len(chunks) > 2 and (execution.eager_workers or _worth_starting(
        ESTIMATE_LOW * sum(costs), ESTIMATE_LOW * max(costs), workers, execution))
    if at_once and _forking(execution):
        return ForkedPool(job, chunks, workers, _record_start)
    return _started_later(job, chunks, workers, execution, costs, at_once)


def _started_later(job: Job, chunks: list[np.ndarray], workers: int, execution: ExecutionOptions,
                   costs: list[float], at_once: bool) -> Iterator[dict]:
    """:func:`run_processes` where the workers do not start at once, or not by a fork."""
    if len(chunks) > 2 and sum(costs) >= START_COST["first"]:
        start_server_early(execution)
    if not at_once:
        with one_thread():  # the first chunk also pays for one-off costs (kernels, solver): time the second
            yield job.solve(chunks[-1])
            seconds = 0.0
            if len(chunks) > 1:
                start = time.perf_counter()
                yield job.solve(chunks[-2])
                seconds = time.perf_counter() - start
        if len(chunks) <= 2:
            return
        chunks, left = chunks[:-2], seconds * sum(costs[:-2]) / costs[-2]
        if not _worth_starting(left, left / len(chunks), workers, execution):
            yield from run_serial(job, chunks, workers, execution)
            return
        if _forking(execution):
            yield from ForkedPool(job, chunks, workers, _record_start)
            return
    start_server_early(execution)  # here, not in the pool's thread, which cannot set signals
    _ensure_server(execution.worker_start)
    pool = FedPool(job, chunks, workers, process_context(execution.worker_start))
    done = False
    try:
        with one_thread():
            while not pool.up():
                for future in pool.finished():
                    yield future.result()
                chunk = pool.take()
                if chunk is None:
                    break
                yield job.solve(chunk)
        for future in pool.collected():
            yield future.result()
        done = True
    finally:
        closing = time.perf_counter()
        pool.close(abandoned=not done)
        if done:
            _record_start(pool, time.perf_counter() - closing)


BACKENDS = {"serial": run_serial, "processes": run_processes, "dask": run_dask}
