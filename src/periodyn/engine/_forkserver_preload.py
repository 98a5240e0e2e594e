"""Imported by the sweep's fork server (:mod:`periodyn.engine.backends`) before it forks workers:
loads the speed solver's compiled kernels once, so that every worker starts with them
instead of loading them from Numba's cache (about 0.2 s per worker start). A failure
here only costs that time: each worker then loads the kernels itself."""

import contextlib

from ..speeds import warm_up

with contextlib.suppress(Exception):
    warm_up()
