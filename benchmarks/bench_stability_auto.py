"""Stability method "auto" against each method, one core, measured side by side.

For the pendulum, the slider-crank (2 rod elements) and the slider-crank scaled to more
rod elements, at several harmonic counts m: speeds per second of
SpeedSolver.solve_many with stability by "dense", "sparse" and "magnus" Hill/monodromy and
by "auto", and the ratio of auto's time to the best Hill method's time and to the best
method's time (magnus included). A method whose estimated time per speed is above the
budget is skipped ("-").

Run: python benchmarks/bench_stability_auto.py [--budget 3] [--quick]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import periodyn  # noqa: E402
from periodyn.analysis import SpeedSolver  # noqa: E402
from periodyn.examples.slider_crank import first_bending_frequency, slider_crank_model  # noqa: E402
from periodyn.hill import method_costs  # noqa: E402
from periodyn.linearize import omega_split  # noqa: E402

METHODS = ("dense", "sparse", "magnus", "auto")


def scaled_slider_crank(elements: int, samples: int = 64):
    """The slider-crank with ``elements`` rod elements, 2 % damping in the first mode."""
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=elements))
    return omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=elements), samples)


def pilot(solver, omegas, budget):
    """Speeds that solve_many treats in about budget / 3 seconds (after a warm-up)."""
    solver.solve_many(omegas[:1])  # jit, cached terms
    done, t0 = 0, time.perf_counter()
    while done < omegas.size and (done == 0 or time.perf_counter() - t0 < budget / 3):
        step = max(1, min(omegas.size - done, done or 1))
        solver.solve_many(omegas[done: done + step])
        done += step
    return done


def row(name, model, m, omegas, budget, rounds=3):
    """Best of ``rounds`` interleaved timings of each method on the same speeds."""
    solvers = {k: SpeedSolver(model, m, method=k) for k in METHODS}
    if method_costs(solvers["dense"].pattern)[0] > budget:
        del solvers["dense"]
    count = {k: pilot(s, omegas, budget) for k, s in solvers.items()}
    times = {k: np.inf for k in solvers}
    for _ in range(rounds):
        for k, s in solvers.items():
            t0 = time.perf_counter()
            s.solve_many(omegas[: count[k]])
            times[k] = min(times[k], (time.perf_counter() - t0) / count[k])
    rates = {k: 1.0 / times[k] if k in times else np.nan for k in METHODS}
    choices = [c for c, _ in solvers["auto"].hill_methods(omegas)]
    auto_choice = "/".join(f"{c} {choices.count(c)}" for c in sorted(set(choices)))
    hill = np.nanmax([rates["dense"], rates["sparse"]])
    best = np.nanmax([rates[k] for k in ("dense", "sparse", "magnus")])
    cells = "".join(f"{rates[k]:10.1f}" if np.isfinite(rates[k]) else f"{'-':>10}" for k in METHODS)
    print(f"{name:<18}{model.n:4d}{m:4d}{cells}   {hill / rates['auto']:9.2f}  {best / rates['auto']:9.2f}  "
          f"{auto_choice}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--budget", type=float, default=3.0, help="seconds per method and case")
    ap.add_argument("--quick", action="store_true", help="fewer cases")
    args = ap.parse_args()
    print(f"{'model':<18}{'n':>4}{'m':>4}" + "".join(f"{k:>10}" for k in METHODS)
          + "  auto/best-Hill  auto/best  auto's choices   (speeds/s)")
    w0 = periodyn.examples.pendulum().metadata["omega0"]
    cases = [("pendulum", lambda p: periodyn.examples.pendulum(samples=p), np.linspace(0.1, 1.4, 200) * w0,
              (4, 12, 32)),
             ("slider-crank", lambda p: periodyn.examples.slider_crank(damping=0.02, samples=p),
              np.linspace(150.0, 300.0, 200), (4, 12, 32, 64))]
    if not args.quick:
        for el in (4, 8):
            cases.append((f"slider-crank x{el}", lambda p, el=el: scaled_slider_crank(el, p),
                          np.linspace(150.0, 300.0, 200), (4, 12, 32)))
    for name, build, omegas, ms in cases:
        for m in ms:
            row(name, build(max(64, 4 * m + 8)), m, omegas, args.budget)  # p >= 4m+1: all couplings kept


if __name__ == "__main__":
    main()
