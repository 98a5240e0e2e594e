"""LLVM optimization level of periodyn's kernels: -O1 instead of Numba's default -O3.

A first run after an install compiles every kernel it calls, and LLVM's optimization of
the linked modules is most of that time (see :mod:`periodyn.kernels`). The kernels are
loops over small dense arrays and calls into each other; -O1 already inlines, promotes to
registers and simplifies them, and the passes -O3 adds (aggressive unrolling, more
inlining, loop transformations) buy nothing measurable here while they double the compile:
``benchmarks/bench_opt_level.py`` compiles and times the same work at both levels side by side.

The level applies only while Numba compiles a periodyn kernel (a ``numba:compile`` event of
a function of ``periodyn.kernels``, callees included) and is restored afterwards, so code
of the user's compiled in the same process keeps Numba's setting. ``NUMBA_OPT`` set in the
environment wins: periodyn then leaves the level alone. Kernels already in the cache are
loaded as they were compiled.
"""

import os

from numba.core import config, event

__all__ = ["KERNEL_OPT_LEVEL", "kernel_opt_level"]

#: LLVM optimization level (0-3) of periodyn's kernels when NUMBA_OPT is not set
KERNEL_OPT_LEVEL = 1


def kernel_opt_level() -> int:
    """The level periodyn's kernels compile at in this process (NUMBA_OPT wins)."""
    return int(config.OPT) if "NUMBA_OPT" in os.environ else KERNEL_OPT_LEVEL


class _KernelLevel(event.Listener):
    """Sets Numba's OPT to :data:`KERNEL_OPT_LEVEL` from the start of the outermost compile
    of a periodyn kernel to its end (Numba compiles under one global lock, so compiles nest
    but never interleave)."""

    def __init__(self):
        self.depth = 0
        self.saved = None

    def on_start(self, ev):
        if self.depth:
            self.depth += 1
        elif ev.data["dispatcher"].py_func.__module__.startswith(__package__ + "."):
            self.depth = 1
            self.saved = config.OPT
            config.OPT = type(config.OPT)(KERNEL_OPT_LEVEL)

    def on_end(self, ev):
        if self.depth:
            self.depth -= 1
            if not self.depth:
                config.OPT = self.saved


if "NUMBA_OPT" not in os.environ:
    event.register("numba:compile", _KernelLevel())
