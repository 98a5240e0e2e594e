"""Imported by the sweep's fork server (:mod:`periodyn.sweep`) before it forks workers:
loads the speed solver's compiled kernels once, so that every worker starts with them
instead of loading them from Numba's cache (about 0.2 s per worker start)."""

from .analysis import warm_up

warm_up()
