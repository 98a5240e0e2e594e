"""Model-building time of the slider-crank against the number of rod elements.

For 2, 4, 8, 16, 32, 64 rod elements (or ``--elements``): compiling the element model and building its
omega-split linearized model (kinematics at every sample, per-sample reduced M, C, K,
f^d, eq. 5-10) on one thread, best of ``--rounds``, and the exponent of a power law
t ~ elements^k fitted to the build times (least squares in log-log). To compare two
trees, run it with each tree first on PYTHONPATH in one shell command.

Run: python benchmarks/bench_model_build.py [--samples 64] [--rounds 3] [--elements 8 16 32 64]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from periodyn.examples.slider_crank_rod import slider_crank_model  # noqa: E402
from periodyn.model.linearization import omega_split  # noqa: E402

ELEMENTS = (2, 4, 8, 16, 32, 64)


def build_time(elements: int, samples: int, rounds: int) -> tuple[float, int]:
    """Best time (s) of compile + omega_split, and the number of dynamic coordinates."""
    best = np.inf
    for _ in range(rounds):
        t0 = time.perf_counter()
        model = omega_split(slider_crank_model(1e-4, rod_elements=elements), samples)
        best = min(best, time.perf_counter() - t0)
    return best, model.n


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--elements", type=int, nargs="+", default=list(ELEMENTS), help="rod element counts")
    args = ap.parse_args()
    elements = sorted(args.elements)
    omega_split(slider_crank_model(1e-4, rod_elements=2), 8)  # load the compiled kernels
    times = []
    print(f"{'elements':>9}{'n_d':>6}{'build s':>10}")
    for el in elements:
        t, n = build_time(el, args.samples, args.rounds)
        times.append(t)
        print(f"{el:9d}{n:6d}{t:10.4f}", flush=True)
    k = np.polyfit(np.log(elements), np.log(times), 1)[0]
    tail = np.polyfit(np.log(elements[-3:]), np.log(times[-3:]), 1)[0]
    print(f"fitted exponent: {k:.2f} over {elements[0]}-{elements[-1]} elements, {tail:.2f} over the last three")


if __name__ == "__main__":
    main()
