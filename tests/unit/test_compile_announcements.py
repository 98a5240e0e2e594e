"""periodyn.engine.warmup.announce_compiles: one line per kernel family Numba compiles."""

import io

import numba
import numpy as np
from numba import njit
from numba.core import event

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
    """compile_ahead: one daemon process compiling the speed solver (and the model's kernels
    whose arrays type it is sent) when the cache is cold and two cores are there, once per
    process; nothing on a warm cache or one core."""
    from periodyn.engine import threads, warmup

    started = []

    class Context:
        def Pipe(self, duplex):
            return "receiver", "sender"

        def Process(self, target, args, daemon, name):
            started.append((target, args, daemon))
            return type("P", (), {"start": lambda self: None})()

    registered = []
    monkeypatch.setattr(warmup, "get_context", lambda kind: Context())
    monkeypatch.setattr(warmup.event, "register", lambda kind, listener: registered.append(listener))
    monkeypatch.setattr(warmup, "_AHEAD", None)
    for cached, cores in ((True, 2), (False, 1), (False, 2), (False, 2)):
        monkeypatch.setattr(warmup, "kernels_cached", lambda: cached)
        monkeypatch.setattr(threads, "available_cores", lambda: cores)
        warmup.compile_ahead()
    assert started == [(warmup._ahead, ("receiver",), True)]
    assert len(registered) == 1 and registered[0].conn == "sender"


def test_the_model_type_is_sent_once_at_the_first_compile_of_an_element_model_kernel():
    from periodyn.engine.warmup import _ModelTypeSender
    from periodyn.kernels.mechanism.constraint_system import SpatialArrays

    sent = []
    sender = _ModelTypeSender(type("C", (), {"send": lambda self, value: sent.append(value)})())
    arrays = numba.typeof(SpatialArrays(*([np.zeros(1, dtype=np.int64)] * 15 + [1, np.zeros(1), np.zeros(1)])))
    other = type("D", (), {"py_func": type("F", (), {"__module__": "periodyn.kernels.solvers.banded"})})()
    mechanism = type("D", (), {"py_func": type("F", (), {"__module__": "periodyn.kernels.mechanism.lu"})})()
    for dispatcher, args in ((other, (arrays,)), (mechanism, (numba.float64,)), (mechanism, (arrays,)),
                             (mechanism, (arrays,))):
        sender.on_start(type("E", (), {"data": {"dispatcher": dispatcher, "args": args}})())
    assert sent == [arrays]


def test_the_ahead_signatures_are_those_a_sweep_compiles():
    """The kernels a compile-ahead process compiles for a spatial element model are the ones
    the model's checks and linearization use: after those ran (their kernels now in the
    cache), compiling them for the model's arrays type compiles nothing."""
    from periodyn.engine import warmup
    from periodyn.examples.cardan import cardan_shaft_model
    from periodyn.model.linearization import omega_split

    model = cardan_shaft_model()  # its checks: the LU's, reduced_sample
    omega_split(model, 4)  # split_sample
    assert [name for _, name, _ in warmup._MODEL_KERNELS["SpatialArrays"]] == [
        "lu_factor", "norm1", "inverse_norm1", "element_arrays"]
    compiled = []

    class Recorder(event.Listener):
        def on_start(self, ev):
            compiled.append(ev.data["dispatcher"].py_func.__qualname__)

        def on_end(self, ev):
            pass

    with event.install_listener("numba:compile", Recorder()):
        warmup._compile_model(numba.typeof(model.arrays))
    assert compiled == []
