"""Imported by the sweep's fork server (:func:`periodyn.engine.pools.process_context`) before it forks workers:
loads the speed solver's compiled kernels once, so that every worker starts with them
instead of loading them from Numba's cache (about 0.2 s per worker start). A failure
here only costs that time: each worker then loads the kernels itself.

Also quiets one failure of a worker that never started: when the sweep stops (Ctrl-C) while
the fork server is handing a new worker its start data, the worker reads a cut-off pickle
and the fork server would print its traceback into the user's terminal after the sweep's
own message; such a worker ends silently (its chunks were never given to it)."""

import contextlib
import pickle
import sys

from ..speeds import warm_up

with contextlib.suppress(Exception):
    warm_up()

_report = sys.excepthook


def _quiet_when_the_sweep_stopped(kind, value, traceback):
    if not issubclass(kind, (pickle.UnpicklingError, EOFError)):
        _report(kind, value, traceback)


sys.excepthook = _quiet_when_the_sweep_stopped
