"""Campbell-diagram cost of the rotor of Schwab & Meijaard (2001), section 4.3.

Prints, in one run (pin threads: OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1):
1. a 1000-speed Campbell diagram (0-8000 rpm, 8 modes) of the paper's 5-element rotor
   with the dense batched eigen-solver (the default for small rotors);
2. the same rotor with 50 elements: the sparse subset solver over all 1000 speeds and
   the dense solver timed on a subset of speeds and scaled, with the largest relative
   difference between the two at the common speeds.

Run: OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1 python benchmarks/bench_campbell.py [--speeds 1000]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from periodyn.examples import rotor
from periodyn.rotor import campbell


def best_time(fun, repeat: int = 3) -> tuple[float, object]:
    """Best wall time of ``repeat`` calls (s) and the last result."""
    best, out = np.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fun()
        best = min(best, time.perf_counter() - t)
    return best, out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", type=int, default=1000)
    args = parser.parse_args()
    speeds = np.linspace(0.0, 8000.0 * np.pi / 30.0, args.speeds)
    small, big = rotor(5), rotor(50)
    t_small, _ = best_time(lambda: campbell(small, speeds, modes=8))
    print(f"5 elements  ({small.n:3d} coordinates), dense,  {args.speeds} speeds: {t_small:7.3f} s")
    t_subset, sub = best_time(lambda: campbell(big, speeds, modes=8, eigensolver="subset"), repeat=1)
    print(f"50 elements ({big.n:3d} coordinates), subset, {args.speeds} speeds: {t_subset:7.3f} s"
          f"  ({t_subset / t_small:.1f}x the 5-element time for {big.n / small.n:.0f}x the coordinates)")
    every = max(1, args.speeds // 50)
    t_dense, dense = best_time(lambda: campbell(big, speeds[::every], modes=8, eigensolver="dense"), repeat=1)
    scaled = t_dense * args.speeds / speeds[::every].size
    diff = np.abs(sub.eigenvalue.values[::every] - dense.eigenvalue.values) / np.abs(dense.eigenvalue.values)
    print(f"50 elements, dense on {speeds[::every].size} speeds scaled to {args.speeds}: {scaled:7.3f} s"
          f"  (subset is {scaled / t_subset:.1f}x faster; largest relative difference {diff.max():.1e}, "
          f"whirls equal: {bool((sub.whirl.values[::every] == dense.whirl.values).all())})")


if __name__ == "__main__":
    main()
