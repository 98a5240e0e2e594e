"""periodyn.engine.warmup.announce_compiles: one line per kernel family Numba compiles."""

import io

import numpy as np
from numba import njit

from periodyn.engine.warmup import FAMILY_SECONDS, STEPS, announce_compiles


def _kernel(module: str):
    """A fresh (never compiled) jitted function whose module is ``module``."""
    namespace = {"__name__": module}
    exec("def twice(x):\n    return 2.0 * x\n", namespace)
    return njit(namespace["twice"])


def test_a_compile_is_announced_once_per_family_with_its_cost():
    stream = io.StringIO()
    announce_compiles(stream)
    try:
        family = next(iter(FAMILY_SECONDS))
        kernel = _kernel(f"periodyn.kernels.{family}")
        assert kernel(1.5) == 3.0
        assert kernel(np.arange(2.0))[1] == 2.0  # a second signature of the same family: no second line
        _kernel("elsewhere")(1.0)  # not a periodyn kernel: not announced
    finally:
        announce_compiles(None)
    lines = stream.getvalue().splitlines()
    assert lines == [f"periodyn: compiling kernels {family} (about {FAMILY_SECONDS[family]:.0f} s of CPU; "
                     "once per install, `periodyn warmup` does it ahead) ..."]


def test_silenced_announcements_say_nothing():
    stream = io.StringIO()
    announce_compiles(stream)
    announce_compiles(None)
    assert _kernel("periodyn.kernels.quiet_family")(1.0) == 2.0
    assert stream.getvalue() == ""


def test_every_warmup_step_has_a_cost_estimate():
    assert all(seconds > 0 for _, seconds, _ in STEPS)


def test_a_cold_cache_compiles_the_solver_ahead_in_a_background_process(monkeypatch):
    """compile_ahead: one daemon process running the speed solver's warm-up step when the
    cache is cold and two cores are there, once per process; nothing on a warm cache or
    one core."""
    from periodyn.engine import threads, warmup

    started = []

    class Context:
        def Process(self, target, args, daemon, name):
            started.append((target, args, daemon))
            return type("P", (), {"start": lambda self: None})()

    monkeypatch.setattr(warmup, "get_context", lambda kind: Context())
    monkeypatch.setattr(warmup, "_AHEAD", None)
    for cached, cores in ((True, 2), (False, 1), (False, 2), (False, 2)):
        monkeypatch.setattr(warmup, "kernels_cached", lambda: cached)
        monkeypatch.setattr(threads, "available_cores", lambda: cores)
        warmup.compile_ahead()
    assert len(started) == 1
    target, (step,), daemon = started[0]
    assert target is warmup._step and daemon and STEPS[step][0].startswith("speed solver")
