"""Cold start: wall time of ``import periodyn`` and of ``periodyn --help``, each the median
of 5 fresh Python processes (one thread per library, as in every benchmark here).

    python benchmarks/bench_import.py            # the tree on PYTHONPATH (or the installed one)

Compare two trees side by side by running it with each on PYTHONPATH, alternating.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import time

RUNS = 5
TARGET = 0.5  # s
CASES = {
    "import periodyn": [sys.executable, "-c", "import periodyn"],
    "periodyn --help": [sys.executable, "-m", "periodyn.cli", "--help"],
}


def wall_times(argv: list[str], env: dict[str, str]) -> list[float]:
    times = []
    for _ in range(RUNS):
        start = time.perf_counter()
        subprocess.run(argv, env=env, check=True, stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - start)
    return times


def main() -> None:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1"}
    subprocess.run(CASES["import periodyn"], env=env, check=True)  # bytecode compiled, files in the page cache
    import periodyn

    print(f"periodyn from {os.path.dirname(periodyn.__file__)}; median of {RUNS} fresh processes")
    for name, argv in CASES.items():
        times = wall_times(argv, env)
        median = statistics.median(times)
        verdict = "under" if median < TARGET else "OVER"
        print(f"  {name:18s} median {median:.3f} s (min {min(times):.3f}, max {max(times):.3f}); "
              f"{verdict} the {TARGET} s target")


if __name__ == "__main__":
    main()
