"""periodyn.kernels.optimization: periodyn's kernels compile at KERNEL_OPT_LEVEL, other
code compiled in the same process keeps Numba's level, and NUMBA_OPT set by the user wins."""

import os
import subprocess
import sys

from numba import njit
from numba.core import config, event

from periodyn.kernels.optimization import KERNEL_OPT_LEVEL, kernel_opt_level


def _fresh(module: str):
    """A never-compiled jitted function whose module is ``module``, calling a second one."""
    namespace = {"__name__": module}
    exec("def inner(x):\n    return x + 1.0\n", namespace)
    namespace["inner"] = njit(namespace["inner"])
    exec("def outer(x):\n    return 2.0 * inner(x)\n", namespace)
    return njit(namespace["outer"])


class _Levels(event.Listener):
    """Numba's OPT at the start and the end of every compile, as (module, level, where)."""

    def __init__(self):
        self.seen = []

    def on_start(self, ev):
        self.seen.append((ev.data["dispatcher"].py_func.__name__, int(config.OPT), "start"))

    def on_end(self, ev):
        self.seen.append((ev.data["dispatcher"].py_func.__name__, int(config.OPT), "end"))


def test_kernels_compile_at_the_kernel_level_and_other_code_at_numbas():
    if "NUMBA_OPT" in os.environ:
        assert kernel_opt_level() == int(config.OPT)
        return
    before = int(config.OPT)
    levels = _Levels()
    with event.install_listener("numba:compile", levels):
        assert _fresh("periodyn.kernels.probe")(1.0) == 4.0
        assert _fresh("user_code")(1.0) == 4.0
    kernel, user = levels.seen[:4], levels.seen[4:]
    assert kernel == [("outer", KERNEL_OPT_LEVEL, "start"), ("inner", KERNEL_OPT_LEVEL, "start"),
                      ("inner", KERNEL_OPT_LEVEL, "end"), ("outer", before, "end")]  # restored before this listener runs
    assert all(level == before for _, level, _ in user) and len(user) == 4
    assert int(config.OPT) == before and kernel_opt_level() == KERNEL_OPT_LEVEL


def test_numba_opt_in_the_environment_wins():
    code = ("from numba.core import config\n"
            "from periodyn.kernels.optimization import kernel_opt_level\n"
            "print(kernel_opt_level(), int(config.OPT))")
    env = dict(os.environ, NUMBA_OPT="2")
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["2", "2"]
