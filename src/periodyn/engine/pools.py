"""Local worker processes of a sweep (:mod:`periodyn.engine.backends` decides which and when).

* :class:`ForkedPool`: forked from the sweep's process once the model is built, where
  :func:`fork_problem` finds nothing against it: the workers hold the job, the built
  models and solvers and the loaded kernels as the sweep's process does, and are up in
  milliseconds (about 10 ms of this process's time per worker, for a 340 MB process).
* :class:`FedPool`: started from a fork server (:func:`process_context`; it imports
  periodyn and loads the solver's kernels once, about 2 s of CPU at its first start) or
  spawned, with the job cloudpickled; fed by a thread while this process solves chunks.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import sys
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, as_completed, wait
from typing import Callable, Iterator

import cloudpickle
import numpy as np

from .job import Job
from .threads import worker_environment
from .workers import init_worker, ready, solve_in_worker

__all__ = ["FedPool", "ForkedPool", "fork_problem", "process_context", "sigint_ignored"]

_POLL = 0.005  # s between checks for the first submission while collecting
_IDLE = 1.0  # s at most that the pool-feeding thread sleeps without news (it is woken by every change)
_EXITING_CHECKS = 5  # counts of the threads, 10 ms apart, before one that is ending is taken as running


def process_context(method: str = "auto"):
    """Start method of a :class:`FedPool`: "forkserver" where available and not ``method``
    "spawn" (a server process imports periodyn and loads the speed solver's compiled
    kernels once, in the one-thread environment of its first start, and forks the
    workers, so pools after the first start in milliseconds), else "spawn"."""
    if method == "spawn" or "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(["periodyn.engine.workers", "periodyn.engine._forkserver_preload"])
    return context


@contextlib.contextmanager
def sigint_ignored() -> Iterator[None]:
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


def _openblas_pool_threads() -> int:
    """Threads of the OpenBLAS pools (pthreads builds) loaded in this process: each stops
    its pool before a fork (its own at-fork handler) and starts it again when needed."""
    from threadpoolctl import ThreadpoolController

    return sum(max(lib.num_threads - 1, 0) for lib in ThreadpoolController().lib_controllers
               if lib.internal_api == "openblas" and getattr(lib, "threading_layer", "") == "pthreads")


def fork_problem() -> str:
    """Why worker processes cannot be forked from this process now ('' when they can). A
    fork copies only the calling thread: a lock that another thread holds stays locked in
    the child for ever. So only on Linux (on macOS system libraries are not fork-safe),
    from the main thread while it is the only Python thread (no pool-feeding thread, no
    progress-bar monitor, no Dask client, no thread of the caller's), and while every
    other thread of the process belongs to an OpenBLAS pool (the threads of an OpenMP
    runtime, e.g. Numba's after a parallel kernel has run, are not fork-safe)."""
    if not sys.platform.startswith("linux") or "fork" not in multiprocessing.get_all_start_methods():
        return "fork is safe only on Linux"
    if threading.current_thread() is not threading.main_thread() or threading.active_count() > 1:
        return "other Python threads run in this process"
    allowed = None
    for _ in range(_EXITING_CHECKS):
        try:
            threads = len(os.listdir("/proc/self/task"))
        except OSError:
            return "the threads of this process cannot be counted"
        if threads == 1:
            return ""
        allowed = 1 + _openblas_pool_threads() if allowed is None else allowed  # a scan only with other threads
        if threads <= allowed:
            return ""
        time.sleep(0.01)  # a thread joined just now may still be ending
    return "threads other than OpenBLAS's run in this process"


class ForkedPool:
    """``processes`` worker processes forked from this process at construction, in this
    thread and before the pool's own threads start (see :func:`fork_problem`), each
    holding the job as this process does; every chunk is submitted at once and runs in
    order. Iterating yields the chunks' results as they complete; ``close()`` (also after
    an interrupt, before or during the iteration) shuts the workers down. ``done`` is
    called with the pool after a complete iteration and the seconds its shutdown took."""

    forked = True

    def __init__(self, job: Job, chunks: list[np.ndarray], processes: int,
                 done: Callable[["ForkedPool", float], None] | None = None):
        self.created = time.perf_counter()
        self.ready_after: float | None = None  # s from creation until a worker was up
        self.done, self.closed = done, False
        with sigint_ignored():  # the workers start with Ctrl-C ignored: the sweep's process decides
            self.pool = ProcessPoolExecutor(max_workers=processes, mp_context=multiprocessing.get_context("fork"),
                                            initializer=init_worker, initargs=(job,))
            first = self.pool.submit(ready)  # forks every worker here (the fork start method starts them at once)
        first.add_done_callback(self._up)
        self.futures = [self.pool.submit(solve_in_worker, chunk) for chunk in chunks]

    def _up(self, _future) -> None:
        self.ready_after = time.perf_counter() - self.created

    def __iter__(self) -> Iterator[dict]:
        complete = False
        try:
            finished, self.futures = as_completed(self.futures), []  # a chunk's result is dropped once yielded
            for future in finished:
                yield future.result()
            complete = True
        finally:
            closing = time.perf_counter()
            self.close(abandoned=not complete)
            if complete and self.done is not None:
                self.done(self, time.perf_counter() - closing)

    def close(self, abandoned: bool = True) -> None:
        """Shut the workers down; ``abandoned``: the sweep stopped taking chunks (Ctrl-C, an
        error), so the workers are terminated rather than waited for."""
        if self.closed:
            return
        self.closed = True
        if abandoned:
            for process in list((getattr(self.pool, "_processes", None) or {}).values()):
                process.terminate()
        self.pool.shutdown(wait=not abandoned, cancel_futures=True)


class FedPool:
    """Local worker processes fed from the front of the chunk list, started by a thread so
    that this process can solve chunks from the back meanwhile (:func:`periodyn.engine.backends.run_processes`).
    Chunks go to the workers only once one of them is up, and at most ``2 * processes``
    at a time, so this process never waits for a worker that is still starting: a sweep
    that ends before then is solved here alone. ``take()`` hands this process the last
    chunk no worker has started: one not yet submitted, or a submitted one whose future
    can still be cancelled (the pool runs its queue in order, so once the last submitted
    chunk runs, every earlier one does)."""

    def __init__(self, job: Job, chunks: list[np.ndarray], processes: int, context):
        self.chunks, self.processes, self.context = chunks, processes, context
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
                self.pool = ProcessPoolExecutor(max_workers=self.processes, mp_context=self.context,
                                                initializer=init_worker, initargs=(payload,))
                self.ready = self.pool.submit(ready)
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
                future = self.pool.submit(solve_in_worker, self.chunks[i])
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
