"""Numba's on-disk cache of the compiled kernels: whether it is filled, and filling it
(``periodyn warmup``) with one progress line per step, so the first sweep after an
install does not spend its first 20-200 s compiling in silence."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path
from typing import Callable, TextIO

__all__ = ["kernels_cached", "warm_up", "STEPS", "COMPILE_NOTE"]

#: kernel modules the speed solver calls at every sweep point
_SOLVER_KERNELS = ("solvers/banded", "solvers/floquet", "solvers/magnus_ladder", "mechanism/outputs")  # kernels/...
COMPILE_NOTE = ("compiling the numerical kernels on first use (once per install, 20-200 s; "
                "`periodyn warmup` does it ahead)")


def kernels_cached() -> bool:
    """True when the speed solver's kernels are in Numba's cache beside the sources (or
    when a NUMBA_CACHE_DIR elsewhere makes that unknowable)."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return True
    kernels = Path(__file__).resolve().parents[1] / "kernels"
    return all(any((kernels / path).parent.glob(f"__pycache__/{Path(path).name}.*.nbi")) for path in _SOLVER_KERNELS)


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

    shooting(elliptic_pendulum_model(), 0.8 * np.sqrt(9.81), method="implicit")


def _dae() -> None:
    from ..nonlinear import ihb
    from ..examples import rod_pendulum

    ihb(rod_pendulum(), 3.6, 3)


#: (what, function) in the order run by :func:`warm_up`
STEPS: tuple[tuple[str, Callable[[], None]], ...] = (
    ("speed solver (harmonic balance, Hill, Magnus monodromy and ladder)", _speed_solver),
    ("element models (kinematics, planar beam/truss/hinge linearization)", _element_models),
    ("spatial element models (spatial beam, joints, rigid bodies: the Cardan shaft)", _spatial_models),
    ("non-linear element models (implicit shooting)", _nonlinear_element_models),
    ("DAE harmonic balance (IHB)", _dae),
)


def warm_up(stream: TextIO | None = None) -> float:
    """Compile (or load) every kernel family once, printing one line per step to
    ``stream`` (stderr by default); returns the seconds taken."""
    stream = stream if stream is not None else sys.stderr
    start = time.perf_counter()
    for i, (what, step) in enumerate(STEPS, 1):
        began = time.perf_counter()
        print(f"warmup [{i}/{len(STEPS)}] {what} ...", end="", file=stream, flush=True)
        step()
        print(f" {time.perf_counter() - began:.1f} s", file=stream, flush=True)
    return time.perf_counter() - start
