"""Cold start: a 1000-speed sweep in a fresh process with 1 and with 2 workers.

Each run is a new Python process (``import periodyn``, building the model, starting the
worker processes and their fork server, loading the compiled kernels from Numba's
cache, solving); the runs alternate between the worker counts, and the median wall
time of each is printed with the ratio 2 workers / 1 worker (below 1: the second
worker pays for its start). Run ``periodyn warmup`` once before, so that the kernels
are in the cache (a cold cache is the first-install case, not this one).

Compare source trees by running it once per tree with ``PYTHONPATH=<tree>/src``.

Run: python benchmarks/bench_cold_start.py [--rounds 3] [--speeds 1000] [--cases pendulum cardan]
"""

import argparse
import os
import subprocess
import sys
import time

import numpy as np

CASES = {
    "pendulum": "periodyn.examples.pendulum(samples=64), np.linspace(0.002, 1.4, {n}) * 3.132091952673165",
    "slider-crank": "periodyn.examples.slider_crank(damping=0.02), np.linspace(150.0, 300.0, {n})",
    "cardan": "periodyn.examples.cardan_shaft(), np.linspace(0.001, 0.999, {n}) * 766.0",
}
SCRIPT = """
import time
t0 = time.perf_counter()
import numpy as np
import periodyn
model, omega = {case}
ds = periodyn.sweep(model, omega, 12, workers={workers}, progress=False)
assert int(ds.attrs["failed_points"]) == 0
print(time.perf_counter() - t0, ds.attrs.get("stability_methods", ds.attrs["method"]).split(";")[0])
"""


def run(case: str, workers: int, speeds: int) -> tuple[float, float, str]:
    """(wall time of the whole process, time inside it from before the import, methods)."""
    code = SCRIPT.format(case=CASES[case].format(n=speeds), workers=workers)
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=os.environ)
    wall = time.perf_counter() - t0
    inside, methods = out.stdout.strip().split(" ", 1)
    return wall, float(inside), methods


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--speeds", type=int, default=1000)
    ap.add_argument("--cases", nargs="+", choices=list(CASES), default=list(CASES))
    args = ap.parse_args()
    print(f"{'model':<14}{'1 worker s':>12}{'2 workers s':>13}{'2/1':>7}   stability methods")
    for case in args.cases:
        times = {1: [], 2: []}
        for _ in range(args.rounds):
            for workers in (1, 2):
                wall, _, methods = run(case, workers, args.speeds)
                times[workers].append(wall)
        t1, t2 = np.median(times[1]), np.median(times[2])
        print(f"{case:<14}{t1:12.2f}{t2:13.2f}{t2 / t1:7.2f}   {methods}", flush=True)


if __name__ == "__main__":
    main()
