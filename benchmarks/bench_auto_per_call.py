"""Per call of characteristic_exponents(system, m, method) on one rheo-linear system:
milliseconds of "auto" against "dense" (pendulum near 0.5 omega0, m = 6 and 12; the
slider-crank at m = 12), in a loop over speeds, one BLAS/Numba thread. To compare with
another tree, run this script with PYTHONPATH pointing at it, alternating, in one shell
command.

Run: python benchmarks/bench_auto_per_call.py [--rounds 3]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import periodyn  # noqa: E402


def per_call(model, speeds, m, method, rounds):
    """Best of rounds of the mean milliseconds per call, and the methods used."""
    used = [periodyn.characteristic_exponents(model.at(w), m, method).method for w in speeds]  # warm-up
    best = np.inf
    for _ in range(rounds):
        t0 = time.perf_counter()
        for w in speeds:
            periodyn.characteristic_exponents(model.at(w), m, method)
        best = min(best, (time.perf_counter() - t0) / speeds.size)
    return 1e3 * best, "/".join(f"{c} {used.count(c)}" for c in sorted(set(used)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    pendulum = periodyn.examples.pendulum(samples=64)
    w0 = pendulum.metadata["omega0"]
    cases = [("pendulum", pendulum, np.linspace(0.45, 0.55, 20) * w0, 6),
             ("pendulum", pendulum, np.linspace(0.45, 0.55, 20) * w0, 12),
             ("slider-crank", periodyn.examples.slider_crank(damping=0.02), np.linspace(150.0, 300.0, 8), 12)]
    print(f"{'model':<14}{'m':>4}{'auto ms':>10}{'dense ms':>10}{'auto/dense':>12}   auto's choices")
    for name, model, speeds, m in cases:
        auto, choices = per_call(model, speeds, m, "auto", args.rounds)
        dense, _ = per_call(model, speeds, m, "dense", args.rounds)
        print(f"{name:<14}{m:4d}{auto:10.3f}{dense:10.3f}{auto / dense:12.2f}   {choices}", flush=True)


if __name__ == "__main__":
    main()
