"""Shipped sweeps by their options and by the default stability method ("auto"), one
process, one thread: points (speeds x grid) per second of periodyn.sweep_file on sweeps/pendulum.toml and
sweeps/slider_crank.toml (their speeds, harmonics and samples), best of ``--rounds``
after a warm-up run. To compare two trees, run it with each tree first on PYTHONPATH,
alternating, in one shell command.

Run: python benchmarks/bench_default_sweep.py [--rounds 3]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import time  # noqa: E402

import periodyn  # noqa: E402
from periodyn.studies.spec import load_sweep_file, project_root  # noqa: E402
from periodyn.engine.front import sweep_file  # noqa: E402


def rate(spec, rounds: int) -> tuple[float, int, str]:
    """Best points/s of a serial sweep_file run of spec, its points and methods used."""
    ds = sweep_file(spec, progress=False)  # jit, caches
    best = float("inf")
    for _ in range(rounds):
        t0 = time.perf_counter()
        ds = sweep_file(spec, progress=False)
        best = min(best, time.perf_counter() - t0)
    points = int(ds["stable"].size)  # speeds x grid points
    methods = str(ds.attrs.get("stability_methods", ds.attrs.get("method", ""))).split(";")[0]
    return points / best, points, methods


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    print(f"periodyn from {os.path.dirname(periodyn.__file__)}")
    for name in ("pendulum", "slider_crank"):
        spec = load_sweep_file(project_root() / "sweeps" / f"{name}.toml")
        for label, s in ((f"file ({spec.method})", spec), ("auto", dataclasses.replace(spec, method="auto"))):
            speeds, points, methods = rate(s, args.rounds)
            print(f"{name:<14}{label:<18}{points:6d} points {speeds:10.1f} points/s   {methods}", flush=True)


if __name__ == "__main__":
    main()
