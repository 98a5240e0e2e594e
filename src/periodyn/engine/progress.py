"""Progress reporting for long sweeps: a tqdm bar on a terminal, plain lines otherwise.

Nothing is shown for sweeps that finish within ``DELAY`` seconds. ``progress`` options:
``None`` (automatic), ``False`` (quiet), ``True`` (always a bar), or a callable
``progress(done, total)`` called after every finished chunk (also shows nothing).
"""

from __future__ import annotations

import shutil
import sys
import time
from typing import Callable

from tqdm import tqdm

__all__ = ["Progress"]

DELAY = 1.0  # s before anything is shown
LINE_INTERVAL = 5.0  # s between plain progress lines


class _Bar(tqdm):
    """tqdm without its monitor thread (which outlives the bar, and while it runs this
    process's next sweeps cannot fork their workers: :func:`periodyn.engine.pools.fork_problem`)."""

    monitor_interval = 0


def _seconds(s: float) -> str:
    s = int(round(s))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}" if s >= 3600 else f"{s // 60}:{s % 60:02d}"


class Progress:
    """Counts finished sweep points: ``update(n)``; use as a context manager."""

    def __init__(self, total: int, initial: int = 0, description: str = "sweep",
                 mode: bool | None | Callable[[int, int], None] = None, stream=None):
        self.total = total
        self.done = initial
        self.initial = initial
        self.description = description
        self.stream = stream if stream is not None else sys.stderr
        self.callback = mode if callable(mode) else None
        self.start = time.perf_counter()
        self.last_line = self.start
        self.bar = None
        self.first: tuple[float, int] | None = None  # (time, done) at the first finished chunk
        if mode is True or (mode is None and self.stream.isatty()):
            size = shutil.get_terminal_size()  # 80 x 24 when the terminal reports 0 x 0
            self.bar = _Bar(total=total, initial=initial, desc=description, unit="pt", delay=DELAY,
                            file=self.stream, ncols=size.columns, nrows=size.lines, smoothing=0.1)
        self.lines = mode is None and self.bar is None

    def __enter__(self) -> "Progress":
        return self

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.close()
        elif self.lines and time.perf_counter() - self.start > DELAY and self.done > self.initial:
            self._line()

    def update(self, n: int) -> None:
        self.done += n
        if self.first is None:
            self.first = (time.perf_counter(), self.done)
        if self.bar is not None:
            self.bar.update(n)
        if self.callback is not None:
            self.callback(self.done, self.total)
        now = time.perf_counter()
        if self.lines and now - self.start > DELAY and now - self.last_line > LINE_INTERVAL:
            self.last_line = now
            self._line()

    def _line(self) -> None:
        now = time.perf_counter()
        elapsed = now - self.start
        if self.first is None:  # nothing finished yet: the kernels are still loading or compiling
            rate, eta = 0.0, "? (loading or compiling the kernels)"
        else:  # rate after the first chunk, which also paid for start-up and compilation
            first_time, first_done = self.first
            rate = (self.done - first_done) / max(now - first_time, 1e-9) if self.done > first_done else \
                (self.done - self.initial) / max(elapsed, 1e-9)
            eta = _seconds((self.total - self.done) / rate) if rate > 0 else "?"
        print(f"{self.description}: {self.done}/{self.total} points ({100 * self.done / max(self.total, 1):.0f} %), "
              f"{rate:.0f} points/s, elapsed {_seconds(elapsed)}, ETA {eta}", file=self.stream, flush=True)
