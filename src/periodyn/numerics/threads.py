"""One BLAS/OpenMP and one Numba thread for the computing paths: sweep workers and the
serial sweep (:mod:`periodyn.engine`), and the non-linear solvers (shooting, IHB,
continuation), whose kernels and LAPACK calls work on small matrices where extra threads
only wait for each other (with the OpenBLAS of numpy 1.26 / scipy 1.11 wheels on a loaded
2-core machine, a Numba kernel calling LAPACK ran 40 times slower with its threads), and
whose results then do not depend on the thread count. Imports only the standard library
at module level."""

from __future__ import annotations

import contextlib
import sys
from typing import Iterator

__all__ = ["limit_threads", "one_thread"]

_CONTROLLER: list = []  # [(modules loaded when scanned, threadpoolctl controller)]
_DEPTH = [0]  # nesting of one_thread blocks in this process


def _controller():
    """threadpoolctl's controller of the thread pools loaded in this process. Scanning
    the loaded libraries costs milliseconds (more than a small sweep), so the controller
    is kept until a module is imported (which may load another BLAS or OpenMP library)."""
    from threadpoolctl import ThreadpoolController

    loaded = len(sys.modules)
    if not _CONTROLLER or _CONTROLLER[0][0] != loaded:
        _CONTROLLER[:] = [(loaded, ThreadpoolController())]
    return _CONTROLLER[0][1]


def limit_threads() -> None:
    """One BLAS/OpenMP and one Numba thread in this (worker) process from now on."""
    import numba

    _controller().limit(limits=1)
    numba.set_num_threads(1)


@contextlib.contextmanager
def one_thread() -> Iterator[None]:
    """One BLAS/OpenMP and one Numba thread inside the block (also usable as a function
    decorator); the caller's settings are restored after it. A block inside another costs
    nothing (entering the outermost one costs about 20 us)."""
    if _DEPTH[0]:
        _DEPTH[0] += 1
        try:
            yield
        finally:
            _DEPTH[0] -= 1
        return
    import numba

    numba_threads = numba.get_num_threads()
    with _controller().limit(limits=1):
        numba.set_num_threads(1)
        _DEPTH[0] = 1
        try:
            yield
        finally:
            _DEPTH[0] = 0
            numba.set_num_threads(numba_threads)
