"""Where a sweep's chunks are solved: in this process ("serial"), on a local pool of worker
processes ("processes", fork server where available) or on a Dask cluster ("dask").
Each backend yields finished chunks (result columns, see :meth:`Job.solve`) in any order;
the Dask one lives in :mod:`periodyn.engine.cluster`.
With local processes, the calling process solves chunks only until the first of the
``workers`` worker processes is up (a short sweep never waits for them), then only
collects: each worker writes its chunks' checkpoint files where it solves them
(``job.writer``) and sends back the chunk (a receipt where results stream), so the
calling process only stores what comes back (a few array copies per chunk).

Local worker processes start with one Numba/BLAS/OpenMP thread each (environment set
before they import numpy; Dask workers started by ``scheduler="local"`` too; on an
existing cluster the threads are limited when a worker receives its first chunk), and
the serial path limits the caller's process to one thread while it solves, so serial,
parallel and distributed results agree bit for bit. The job reaches each worker once.
Local workers ignore Ctrl-C: the sweep's process stops between chunks
(:mod:`periodyn.engine.session`) and shuts them down.
"""

from __future__ import annotations

import atexit
import contextlib
import multiprocessing
import os
import signal
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, as_completed, wait
from typing import Iterator

import cloudpickle
import numpy as np

from .cluster import run_dask
from .job import Job
from .options import ExecutionOptions
from .stream import receipt
from ..numerics.threads import limit_threads, one_thread
from .threads import worker_environment

__all__ = ["BACKENDS", "run_serial", "run_processes", "start_server_early"]

_WORKER_JOB: Job | None = None
_POLL = 0.005  # s between checks for the first submission while collecting
_IDLE = 1.0  # s at most that the pool-feeding thread sleeps without news (it is woken by every change)


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
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C reaches the whole group: the sweep's process decides
    limit_threads()
    _WORKER_JOB = cloudpickle.loads(payload)


def _solve_in_worker(indices: np.ndarray) -> dict[str, np.ndarray]:
    """The chunk's results; with ``job.writer`` (the sweep's checkpoint) written here first and
    marked ``written``, or only a receipt of them where the results stream (``job.streamed``).
    The results come back rather than being read back from the checkpoint file: unpickling a
    chunk and storing its columns costs the sweep's process about 0.15 ms, reading its file 6 ms."""
    chunk = _WORKER_JOB.solve(indices)
    if _WORKER_JOB.writer is None:
        return chunk
    _WORKER_JOB.writer.write(chunk)
    return receipt(chunk) if _WORKER_JOB.streamed else {"written": np.True_, **chunk}


def run_serial(job: Job, chunks: list[np.ndarray], workers: int, execution: ExecutionOptions) -> Iterator[dict]:
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
    context.set_forkserver_preload([__name__, "periodyn.engine._forkserver_preload"])
    return context


def _ready() -> None:
    """A task that returns once a worker has started (imports, job loaded)."""


class _Pool:
    """Local worker processes fed from the front of the chunk list, started by a thread so
    that this process can solve chunks from the back meanwhile (:func:`run_processes`).
    Chunks go to the workers only once one of them is up, and at most ``2 * processes``
    at a time, so this process never waits for a worker that is still starting: a sweep
    that ends before then is solved here alone. ``take()`` hands this process the last
    chunk no worker has started: one not yet submitted, or a submitted one whose future
    can still be cancelled (the pool runs its queue in order, so once the last submitted
    chunk runs, every earlier one does)."""

    def __init__(self, job: Job, chunks: list[np.ndarray], processes: int):
        self.chunks, self.processes = chunks, processes
        self.front, self.back = 0, len(chunks)  # chunks[:front] submitted, chunks[back:] taken here
        self.submitted: list = []
        self.lock = threading.Lock()
        self.pool: ProcessPoolExecutor | None = None
        self.ready = None  # the future of _ready
        self.created = time.perf_counter()
        self.ready_after: float | None = None  # s from creation until a worker was up
        self.error: BaseException | None = None
        self.fed = self.orphaned = False  # the feeding thread has ended; closed while the pool was starting
        self.changed = threading.Event()  # wakes the feeding thread: a worker up, a chunk done or taken, closed
        self.thread = threading.Thread(target=self._feed, args=(cloudpickle.dumps(job),), name="periodyn-pool-start",
                                       daemon=True)
        self.thread.start()

    def _up(self, _future) -> None:
        self.ready_after = time.perf_counter() - self.created
        self.changed.set()

    def _news(self, _future=None) -> None:
        self.changed.set()

    def _await_news(self) -> None:
        """Sleep until something changed (the caller checks what), without polling."""
        self.changed.wait(_IDLE)
        self.changed.clear()

    def _left(self) -> bool:
        with self.lock:
            return self.front < self.back

    def _feed(self, payload: bytes) -> None:
        try:
            with worker_environment():  # the processes start with the first submission
                self.pool = ProcessPoolExecutor(max_workers=self.processes, mp_context=_process_context(),
                                                initializer=_init_worker, initargs=(payload,))
                self.ready = self.pool.submit(_ready)
                self.ready.add_done_callback(self._up)
            while self._left() and not self.ready.done():
                self._await_news()
            while self._left():
                with self.lock:
                    busy = [f for f in self.submitted if not f.done()]
                if len(busy) >= 2 * self.processes:
                    self._await_news()
                    continue
                with self.lock:
                    if self.front >= self.back:
                        return
                    i, self.front = self.front, self.front + 1
                future = self.pool.submit(_solve_in_worker, self.chunks[i])
                future.add_done_callback(self._news)
                with self.lock:
                    self.submitted.append(future)
        except BaseException as exc:  # re-raised in the sweep's thread
            self.error = exc
        finally:
            with self.lock:
                self.fed = True
            if self.orphaned:
                self._stop(wait=False)

    def up(self) -> bool:
        """Whether a worker is up (a pool that failed to start never is: this process goes on alone)."""
        ready = self.ready
        return ready is not None and ready.done() and not ready.cancelled() and ready.exception() is None

    def collected(self) -> Iterator:
        """The futures of the chunks the workers solve, as they complete (this process waits
        in between, using no CPU); none, without waiting for the pool's start, when this
        process took every chunk."""
        while True:
            with self.lock:
                fed, busy, none = self.fed, list(self.submitted), self.back == 0
            yield from self.finished()
            if fed or none:
                break
            if busy:
                wait(busy, timeout=_IDLE, return_when=FIRST_COMPLETED)
            else:
                time.sleep(_POLL)
        yield from self.remaining()

    def take(self) -> np.ndarray | None:
        """The next chunk for this process, or None when the workers have all the rest."""
        self.changed.set()  # the feeding thread checks what is left
        with self.lock:
            if self.front < self.back:
                self.back -= 1
                return self.chunks[self.back]
            if self.submitted and self.submitted[-1].cancel():
                self.submitted.pop()
                self.back -= 1
                return self.chunks[self.back]
        return None

    def finished(self) -> list:
        """Futures done so far, removed from the pool's list."""
        with self.lock:
            done = [f for f in self.submitted if f.done()]
            self.submitted = [f for f in self.submitted if not f.done()]
        return done

    def remaining(self) -> Iterator:
        """The futures not yet collected, as they complete (after the last submission); none,
        without waiting for the pool, when this process took every chunk."""
        with self.lock:
            if self.front == 0:  # the workers got no chunk and can get none now
                return
        self.thread.join()
        if self.error is not None:
            raise self.error
        yield from as_completed(self.submitted)

    def close(self, abandoned: bool = False) -> None:
        """Shut the workers down; ``abandoned``: the sweep stopped taking chunks (Ctrl-C,
        an error), so the chunks they are solving are not waited for. A pool whose workers
        are not up yet is not waited for either (its first start may take seconds)."""
        with self.lock:
            self.back = self.front  # nothing more to submit
            up = self.ready is not None and self.ready.done()
        self.changed.set()
        with self.lock:
            if not (up or self.fed):  # still starting (the fork server may be loading): not waited for,
                self.orphaned = True  # the feeding thread stops the pool once it has it
                return
        self.thread.join()
        self._stop(wait=up and not abandoned)

    def _stop(self, wait: bool) -> None:
        """Shut the pool down; unless ``wait``, its processes are terminated first."""
        if self.pool is None:
            return
        if not wait:  # no chunk went to the workers, or none is wanted: stop them now
            for process in list((getattr(self.pool, "_processes", None) or {}).values()):
                process.terminate()
        self.pool.shutdown(wait=wait, cancel_futures=True)


#: Seconds that starting local workers costs this process: the wait until the first worker
#: is up plus the pool's shutdown. The first pool of a process starts the fork server, which
#: imports periodyn and loads the compiled kernels; later pools fork from it. The values are
#: priors until a pool of this process has been timed, then the latest measurement.
START_COST = {"first": 2.0, "later": 0.2}
#: Measured chunk times were 0.8-2.9 times their estimate (:meth:`periodyn.speeds.SpeedSolver.speed_costs`):
#: workers start without timing chunks first where they pay even at this fraction of the estimate.
ESTIMATE_LOW = 0.5
_STARTED: list[bool] = []  # a pool was started in this process
_SERVER_SINCE: list[float] = []  # when this process started the fork server ahead of its first pool


def start_server_early() -> None:
    """Start the fork server (imports and kernel loading, :func:`_process_context`) before
    the first pool of this process, so that it warms up on another core while this
    process builds the model and solves its first chunks; nothing with the "spawn" start
    method or once started. A server no
    pool used is stopped when this process exits: it holds this process's output pipes
    and would keep a caller reading them waiting until its warm-up ends."""
    context = _process_context()
    if _STARTED or _SERVER_SINCE or context.get_start_method() != "forkserver":
        return
    from multiprocessing import forkserver

    _ensure_server()
    _SERVER_SINCE.append(time.perf_counter())
    pid = getattr(forkserver._forkserver, "_forkserver_pid", None)
    if pid is not None:
        atexit.register(_stop_unused_server, pid)


@contextlib.contextmanager
def _sigint_ignored() -> Iterator[None]:
    """Processes started inside inherit SIGINT ignored: Ctrl-C reaches the whole process
    group, and a helper process hit while it imports would print a traceback; the sweep's
    process decides (:mod:`periodyn.engine.session`). Only the main thread sets signals."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous if previous is not None else signal.default_int_handler)


def _ensure_server() -> None:
    """Start the fork server (and the resource tracker) from this thread, with one thread
    per process and SIGINT ignored, where workers are forked from one."""
    if _process_context().get_start_method() == "forkserver":
        from multiprocessing import forkserver

        with worker_environment(), _sigint_ignored():
            forkserver.ensure_running()


def _stop_unused_server(pid: int) -> None:
    if not _STARTED:
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGTERM)


def _start_cost() -> float:
    """Expected seconds until a worker is up: START_COST "later" after the first pool; for
    the first, "first" less the time the fork server has already had (at least "later")."""
    if _STARTED:
        return START_COST["later"]
    if _SERVER_SINCE:
        return max(START_COST["later"], START_COST["first"] - (time.perf_counter() - _SERVER_SINCE[0]))
    return START_COST["first"]


def _worth_starting(left: float, chunk_seconds: float, workers: int) -> bool:
    """Whether ``workers`` worker processes would finish the chunks left (``left``
    estimated seconds, chunks of about ``chunk_seconds``) sooner than this process alone.
    This process keeps solving while they start (:data:`START_COST`); the work left then
    is shared by the ``workers`` processes, which saves ``(left - start) (1 - 1/workers)``;
    that must exceed the expected wait for the last chunk sent to a worker (half a chunk)."""
    return (left - _start_cost()) * (1.0 - 1.0 / workers) > 0.5 * chunk_seconds


def _record_start(pool: "_Pool", closed: float) -> None:
    """Store the measured start (until a worker was up, plus ``closed`` s of shutdown) of a
    pool after the first as ``START_COST["later"]``."""
    if _STARTED and pool.ready_after is not None:
        START_COST["later"] = pool.ready_after + closed
    elif _STARTED:  # closed before a worker was up: its start took at least that long
        START_COST["later"] = max(START_COST["later"], time.perf_counter() - pool.created)
    if pool.ready_after is not None:  # a worker came up: the fork server is ready for the next pools
        _STARTED.append(True)


def run_processes(job: Job, chunks: list[np.ndarray], workers: int, execution: ExecutionOptions) -> Iterator[dict]:
    """``workers`` local worker processes. Where the chunks' estimated costs
    (:meth:`Job.point_costs`) make the workers pay even at :data:`ESTIMATE_LOW` times the
    estimate (:func:`_worth_starting`), they start at once (``execution.eager_workers``:
    whatever the estimate). Otherwise this process (one thread, as the serial path) solves
    the last two chunks first and times the second; the rest is estimated from that time
    scaled by the chunks' estimated costs (at low speeds a chunk may cost many times the
    last one), and unless the workers would finish the rest sooner, counting their measured
    start, it solves them alone. Once started, the workers take chunks from the front while
    this process solves chunks from the back until the first worker is up, so a short sweep
    never waits for them; from then on it only collects what the workers finish. The fork
    server of the first pool starts at once where the chunks are estimated to take longer
    than its start (:func:`start_server_early`)."""
    costs = [float(job.point_costs(c).sum()) for c in chunks]  # estimated seconds per chunk
    if len(chunks) > 2 and sum(costs) >= START_COST["first"]:
        start_server_early()
    at_once = len(chunks) > 2 and (execution.eager_workers
                                   or _worth_starting(ESTIMATE_LOW * sum(costs), ESTIMATE_LOW * max(costs), workers))
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
        if not _worth_starting(left, left / len(chunks), workers):
            yield from run_serial(job, chunks, workers, execution)
            return
    start_server_early()  # here, not in the pool's thread, which cannot set signals
    _ensure_server()
    pool = _Pool(job, chunks, workers)
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
