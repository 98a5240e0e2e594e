"""Numba's on-disk cache of the compiled kernels: whether it is filled, filling it
(``periodyn warmup``, the independent kernel families in parallel processes) with one
progress line per step, and one line per kernel family that a first sweep compiles
(:func:`announce_compiles`), so no first run compiles in silence.

Parallel processes share the cache safely: Numba writes each cache file to a temporary
name and renames it into place, so a reader never sees a partial file; two processes
compiling the same kernel both write it (the same code), and at worst one's index entry
replaces the other's, which costs a recompile later, never a wrong kernel."""

from __future__ import annotations

import contextlib
import os
import sys
import time
import warnings
from concurrent.futures import ProcessPoolExecutor, as_completed
from multiprocessing import get_context
from pathlib import Path
from typing import Callable, TextIO

from numba.core import event

__all__ = ["kernels_cached", "compile_ahead", "warm_up", "announce_compiles", "STEPS", "COMPILE_NOTE"]

#: kernel modules the speed solver calls at every sweep point
_SOLVER_KERNELS = ("solvers/banded", "solvers/floquet", "solvers/magnus_ladder", "mechanism/outputs")  # kernels/...
COMPILE_NOTE = ("compiling the numerical kernels on first use (once per install, 25-125 s of CPU; "
                "`periodyn warmup` does it ahead)")


def kernels_cached() -> bool:
    """True when the speed solver's kernels are in Numba's cache: beside the sources, or
    in NUMBA_CACHE_DIR where that is set (in the folder Numba derives from the sources' path)."""
    kernels = Path(__file__).resolve().parents[1] / "kernels"

    def folder(source: Path) -> Path:
        cache_dir = os.environ.get("NUMBA_CACHE_DIR")
        if not cache_dir:
            return source.parent / "__pycache__"
        from numba.core.caching import UserProvidedCacheLocator

        return Path(cache_dir) / UserProvidedCacheLocator.get_suitable_cache_subpath(str(source))

    return all(any(folder(kernels / f"{path}.py").glob(f"{Path(path).name}.*.nbi")) for path in _SOLVER_KERNELS)


def _speed_solver() -> None:
    from ..speeds import warm_up as solver_warm_up

    solver_warm_up()


def _element_models() -> None:
    from ..speeds import SpeedSolver
    from ..examples import slider_crank

    model = slider_crank(samples=16)
    SpeedSolver(model, 3, stability="magnus").solve_many([200.0])


def _spatial_models() -> None:
    from ..speeds import SpeedSolver
    from ..examples import cardan_shaft

    SpeedSolver(cardan_shaft(samples=32), 6, stability="magnus").solve_many([400.0])


def _nonlinear_element_models() -> None:
    import numpy as np

    from ..examples.elliptic_pendulum import elliptic_pendulum_model
    from ..nonlinear import shooting

    shooting(elliptic_pendulum_model(), 0.8 * np.sqrt(9.81), integrator="implicit")


def _spatial_nonlinear_element_models() -> None:
    from ..errors import ConvergenceError
    from ..examples import cardan_shaft_nonlinear
    from ..nonlinear import shooting

    with contextlib.suppress(ConvergenceError):  # two Newton steps on a coarse map compile every kernel
        shooting(cardan_shaft_nonlinear(), 400.0, integrator="implicit", steps=16, max_iter=2)


def _dae() -> None:
    from ..nonlinear import ihb
    from ..examples import rod_pendulum

    ihb(rod_pendulum(), 3.6, 3)


#: (what, CPU seconds a cold compile takes on one core, function), in the order reported;
#: measured at -O1: the speed solver and implicit shooting by benchmarks/bench_opt_level.py,
#: planar and spatial element models by the slider-crank and Cardan-shaft element sweeps
#: (less the solver), the Cardan shaft's shooting by CI's figure test without this step,
#: the DAE by bench_cold_start.py
STEPS: tuple[tuple[str, float, Callable[[], None]], ...] = (
    ("speed solver (harmonic balance, Hill, Magnus monodromy and ladder)", 32.0, _speed_solver),
    ("element models (kinematics, planar beam/truss/hinge linearization)", 40.0, _element_models),
    ("spatial element models (spatial beam, joints, rigid bodies: the Cardan shaft)", 60.0, _spatial_models),
    ("non-linear element models (implicit shooting)", 75.0, _nonlinear_element_models),
    ("spatial non-linear element models (implicit shooting of the Cardan shaft)", 100.0,
     _spatial_nonlinear_element_models),
    ("DAE harmonic balance (IHB)", 26.0, _dae),
)


def _step(i: int) -> float:
    """Run STEPS[i] (here or in a worker process); returns its seconds. Its solutions only
    exercise the kernels (a few harmonics, one speed), so their accuracy warnings are muted."""
    began = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        STEPS[i][2]()
    return time.perf_counter() - began


#: the kernels a compile-ahead process compiles for an element model, per class of its
#: packed arrays, before the speed solver, as (module under periodyn.kernels, function,
#: arguments: "arrays" the model's packed arrays, a number the dimensions of a C-contiguous
#: float64 array, "pivots" an int64 vector, ("default", v) an argument left at its default).
#: A first sweep compiles the deformation families first (the constraint equations, about a
#: third of a spatial model's compile), then the constraint Jacobian's LU checks and the
#: per-sample kernels, which also need the element arrays (the inertia families): for a
#: spatial model the ahead process compiles the LU checks and the element arrays meanwhile,
#: and the sweep's process loads them (the Cardan shaft: 56 s of CPU in the sweep's process,
#: against 104). A planar model's own compile (about 35 s) is no longer than the solver's,
#: so there the ahead process goes straight to the solver.
_SPATIAL_KERNELS = (("mechanism.lu", "lu_factor", (2, "pivots")), ("mechanism.lu", "norm1", (2,)),
                    ("mechanism.lu", "inverse_norm1", (2, "pivots", ("default", 5))),
                    ("mechanism.assembly", "element_arrays", ("arrays", 1, 1, 1, 2, 3, 4, 3, 3, 3, 1)))
_MODEL_KERNELS = {"SpatialArrays": _SPATIAL_KERNELS, "ModelArrays": _SPATIAL_KERNELS}
#: seconds a compile-ahead process waits, once started, for the arrays type of the model
_MODEL_WAIT = 1.0


def _signatures(arrays_type, kernels) -> list:
    """[(dispatcher, signature)] of ``kernels`` (as in :data:`_MODEL_KERNELS`) for an element
    model whose packed arrays have the Numba type ``arrays_type``."""
    from importlib import import_module

    from numba.core import types

    def arg(spec):
        if spec == "arrays":
            return arrays_type
        if spec == "pivots":
            return types.Array(types.int64, 1, "C")
        return types.Omitted(spec[1]) if isinstance(spec, tuple) else types.Array(types.float64, spec, "C")

    return [(getattr(import_module(f"periodyn.kernels.{module}"), name), tuple(arg(a) for a in spec))
            for module, name, spec in kernels]


def _compile_model(arrays_type) -> None:
    """Compile (or load from the cache) the :data:`_MODEL_KERNELS` of the arrays type's
    class for that type, in order."""
    for dispatcher, signature in _signatures(arrays_type, _MODEL_KERNELS.get(arrays_type.instance_class.__name__, ())):
        dispatcher.compile(signature)


def _ahead(conn) -> None:
    """The compile-ahead process: the :data:`_MODEL_KERNELS` of the element model whose
    arrays type arrives on ``conn`` within :data:`_MODEL_WAIT` s (none for a model without
    elements), then the speed solver."""
    import numba  # noqa: F401  (imported before the wait: the type unpickles to Numba types)

    if conn.poll(_MODEL_WAIT):
        _compile_model(conn.recv())
    _step(next(i for i, (_, _, step) in enumerate(STEPS) if step is _speed_solver))


class _ModelTypeSender(event.Listener):
    """Sends, once, the Numba type of the packed arrays of the first element model whose
    kernels Numba compiles in this process (a cache miss) to the compile-ahead process."""

    def __init__(self, conn):
        self.conn = conn

    def on_start(self, ev):
        from ..kernels.mechanism.constraint_system import ModelArrays, PlanarArrays, SpatialArrays

        args = ev.data["args"]
        if self.conn is None or not args or not ev.data["dispatcher"].py_func.__module__.startswith(
                "periodyn.kernels.mechanism."):
            return
        if getattr(args[0], "instance_class", None) in (ModelArrays, PlanarArrays, SpatialArrays):
            with contextlib.suppress(OSError):  # the process has ended: nothing to tell
                self.conn.send(args[0])
            self.conn = None

    def on_end(self, ev):
        pass


def compile_ahead() -> None:
    """On a cold cache and two or more cores, compile kernels in a background process while
    this one goes on building the model (which compiles the model's own kernel families
    here): the speed solver's and, for a spatial element model, its LU checks and element
    arrays (:data:`_MODEL_KERNELS`; the process is told the model's arrays type at this
    process's first compile of the model's kernels). A first sweep then waits for the
    larger of the two compiles, not their sum. The process ends with this one; a kernel it
    has not finished is compiled here when first called (cache files are written whole,
    see above). At most one such process per process."""
    global _AHEAD
    from .threads import available_cores

    if _AHEAD is None and available_cores() >= 2 and not kernels_cached():
        context = get_context("spawn")
        receiver, sender = context.Pipe(duplex=False)
        _AHEAD = context.Process(target=_ahead, args=(receiver,), daemon=True, name="periodyn-compile-ahead")
        _AHEAD.start()
        event.register("numba:compile", _ModelTypeSender(sender))


_AHEAD = None


def warm_up(stream: TextIO | None = None, processes: int | None = None) -> float:
    """Compile (or load) every kernel family once, printing one line per step to
    ``stream`` (stderr by default) as it finishes; returns the seconds taken. The steps
    run in ``processes`` fresh processes (default: one per core, at most one per step),
    the costliest first; 1 runs them here, in order."""
    from .threads import available_cores

    stream = stream if stream is not None else sys.stderr
    start = time.perf_counter()
    k = len(STEPS)
    processes = min(k, processes or available_cores())
    if processes <= 1:
        for i, (what, _, _) in enumerate(STEPS):
            print(f"warmup [{i + 1}/{k}] {what} ...", end="", file=stream, flush=True)
            print(f" {_step(i):.1f} s", file=stream, flush=True)
        return time.perf_counter() - start
    total = sum(s[1] for s in STEPS)
    print(f"warmup: {k} kernel families in {processes} processes (about {total / processes:.0f}-{total:.0f} s "
          "on an idle machine) ...", file=stream, flush=True)
    order = sorted(range(k), key=lambda i: -STEPS[i][1])
    with ProcessPoolExecutor(processes, mp_context=get_context("spawn")) as pool:
        futures = {pool.submit(_step, i): i for i in order}
        for future in as_completed(futures):
            i = futures[future]
            print(f"warmup [{i + 1}/{k}] {STEPS[i][0]} ... {future.result():.1f} s", file=stream, flush=True)
    return time.perf_counter() - start


#: CPU seconds (one core, cold cache, numba 0.68, LLVM -O1) of the outermost compiles of
#: each kernel module in a first run, callees included (``benchmarks/compile_profile.py`` on
#: the slider-crank and Cardan-shaft element sweep files: the larger of the two, here the
#: Cardan shaft's; a planar model compiles the mechanism modules in about 60 % of these; for
#: a spatial model on two cores, the compile-ahead process takes about half of "assembly")
FAMILY_SECONDS = {"mechanism.split": 13.0, "mechanism.constraint_system": 20.0, "mechanism.assembly": 22.0,
                  "solvers.magnus_ladder": 22.0, "mechanism.transfer": 7.0, "solvers.floquet": 7.0,
                  "solvers.banded": 5.0}


class _Announcer(event.Listener):
    """One line on ``stream`` when Numba starts compiling (a cache miss) a periodyn kernel
    family not compiled before in this process, with its usual cost, and one when a long
    compile ends; kernels compiled inside another count as its family's."""

    def __init__(self):
        self.stream = None
        self.registered = False
        self.depth = 0
        self.began = None
        self.family = ""
        self.seen = set()

    def on_start(self, ev):
        self.depth += 1
        module = ev.data["dispatcher"].py_func.__module__
        if self.depth > 1 or self.stream is None or not module.startswith("periodyn.kernels."):
            return
        self.family = module.removeprefix("periodyn.kernels.")
        self.began = time.perf_counter()
        if self.family not in self.seen:
            self.seen.add(self.family)
            about = FAMILY_SECONDS.get(self.family)
            cost = f"about {about:.0f} s" if about else "a few s"
            print(f"periodyn: compiling kernels {self.family} ({cost} of CPU; once per install, "
                  "`periodyn warmup` does it ahead) ...", file=self.stream, flush=True)

    def on_end(self, ev):
        self.depth -= 1
        if self.depth == 0 and self.began is not None:
            seconds = time.perf_counter() - self.began
            self.began = None
            if seconds > 10.0 and self.stream is not None:
                print(f"periodyn: compiled {self.family} in {seconds:.0f} s", file=self.stream, flush=True)


_ANNOUNCER = _Announcer()


def announce_compiles(stream: TextIO | None) -> None:
    """From now on in this process, say on ``stream`` (None: nothing) which kernel family
    Numba compiles and about how long it takes, one line per family; loading from the
    cache says nothing."""
    if stream is not None and not _ANNOUNCER.registered:
        event.register("numba:compile", _ANNOUNCER)
        _ANNOUNCER.registered = True
    _ANNOUNCER.stream = stream
