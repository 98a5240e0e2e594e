"""Linearization and sweep throughput of the slider-crank (Schwab & Meijaard 2001, 4.2).

Prints, in one run:
1. per-sample linearization (kinematics derivatives + element assembly + reduction,
   eq. 5-10) with the jitted kernel vs its plain-NumPy twin from the tests, and the
   per-sample cost of the parallel (prange) filling of a whole period;
2. a 1000-speed sweep, without and with stability, on one core using the omega-split
   model (SpeedSolver.solve_many, the sweep path) vs re-linearizing at every speed
   (rheo_linear + solve_point with the same stability method, timed on a subset and scaled).

Run: python benchmarks/bench_linearize.py [--speeds 1000] [--samples 64] [--harmonics 12]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")  # "one core" for the sweep comparison

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the project root: tests/twins/planar.py
from tests.twins.planar import kernel_sample, motion_twin  # noqa: E402  (the NumPy twin; needs no pytest)

import periodyn  # noqa: E402
from periodyn.speeds import SpeedSolver  # noqa: E402
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model  # noqa: E402
from periodyn.kernels.mechanism.assembly import reduced_sample  # noqa: E402
from periodyn.model.kinematics import nominal_configurations  # noqa: E402
from periodyn.model.linearization import omega_split, rheo_linear  # noqa: E402
from periodyn.engine.front import sweep  # noqa: E402


def best_time(fun, repeat: int = 5, number: int = 1) -> float:
    """Best wall time of ``number`` calls, s per call."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fun()
        times.append((time.perf_counter() - t0) / number)
    return min(times)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speeds", type=int, default=1000)
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--harmonics", type=int, default=12)
    ap.add_argument("--relinearize-subset", type=int, default=50)
    ap.add_argument("--method", default="magnus", help="stability method (magnus, dense, sparse, auto)")
    args = ap.parse_args(argv)

    w1 = first_bending_frequency(slider_crank_model())
    model = slider_crank_model(2 * 0.02 / w1)
    X = nominal_configurations(model, args.samples)
    qdot = np.array([200.0, 0, 0, 0, 0])
    qddot = np.zeros(5)
    x = X[args.samples // 3]
    p, n, nd = args.samples, model.n_coordinates, model.n_dynamic
    outs = (np.empty((p, nd, nd)), np.empty((p, nd, nd)), np.empty((p, nd, nd)), np.empty((p, nd)),
            np.empty((p, n, nd)), np.empty((p, n, nd)), np.empty((p, n, nd)))
    load = np.zeros(n)

    def fill():  # every sample of a period, one kernel call each (as model.linearization does)
        for j in range(p):
            reduced_sample(model.arrays, X[j], qdot, qddot, load, *(o[j] for o in outs))
    fill()  # compile
    t_jit = best_time(fill, number=20) / p
    t_call = best_time(lambda: kernel_sample(model, x, qdot, qddot), number=200)
    t_np = best_time(lambda: motion_twin(model, x, qdot, qddot), number=20)
    omega_split(model, args.samples)  # compile
    t_split = best_time(lambda: omega_split(model, args.samples), repeat=3)

    print(f"slider-crank: n_x = {model.n_coordinates}, n_d = {model.n_dynamic}, p = {args.samples}, "
          f"numba threads = {os.environ['NUMBA_NUM_THREADS']}")
    print("per-sample linearization          jitted        NumPy twin    speed-up")
    print(f"  per sample in a period fill     {t_jit * 1e6:9.1f} us  {t_np * 1e6:10.1f} us  {t_np / t_jit:8.1f}x")
    print(f"  one sample via Python call      {t_call * 1e6:9.1f} us  {t_np * 1e6:10.1f} us  {t_np / t_call:8.1f}x")
    print(f"  omega-split model, {args.samples} samples: {t_split * 1e3:.2f} ms total "
          f"({t_split / args.samples * 1e6:.1f} us/sample incl. Newton, 3 speeds, output maps)")

    omega = np.linspace(150.0, 300.0, args.speeds)
    split = omega_split(model, args.samples, name="slider_crank")
    subset = omega[:: max(1, args.speeds // args.relinearize_subset)]
    for stability in (False, True):
        label = f"with stability (method {args.method})" if stability else "periodic solution only"
        solver = SpeedSolver(split, args.harmonics, stability=args.method if stability else False)
        solver.solve_many(omega[:2])  # warm-up (jit, caches)
        t_split = best_time(lambda: solver.solve_many(omega), repeat=3)
        relin = lambda: [periodyn.solve_point(rheo_linear(model, w, args.samples), args.harmonics,  # noqa: E731
                                              stability=args.method if stability else False) for w in subset]
        relin()
        t_relin = best_time(relin, repeat=2) / subset.size * args.speeds
        print(f"{args.speeds}-speed sweep, {label} (m = {args.harmonics}, one core)")
        print(f"  omega-split (SpeedSolver.solve_many): {t_split:8.3f} s  {args.speeds / t_split:8.0f} speeds/s")
        print(f"  re-linearize every speed:             {t_relin:8.3f} s  {args.speeds / t_relin:8.0f} speeds/s "
              f"(timed on {subset.size} speeds)")
        print(f"  speed-up: {t_relin / t_split:.1f}x")
    t0 = time.perf_counter()
    sweep(split, omega, args.harmonics, stability=args.method, workers=1, progress=False)
    t = time.perf_counter() - t0
    print(f"  periodyn.sweep (omega-split, stability, workers=1, incl. result dataset): {t:.2f} s  "
          f"{args.speeds / t:.0f} speeds/s")

if __name__ == "__main__":
    main()
