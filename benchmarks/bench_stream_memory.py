"""Client peak memory of a pendulum parameter-grid sweep written to a file, results streamed
(OutputOptions(stream=True): chunks to their checkpoint files, the result file written block by
block from them) against results assembled in memory (stream=False), side by side, for
growing numbers of points.

Each sweep runs in a fresh process (the peak resident set, getrusage ru_maxrss, is per
process); the process first imports periodyn and runs a tiny sweep (kernels loaded), and
its resident set then is the baseline. Printed: points, seconds, baseline and peak (MiB),
growth = peak - baseline, and bytes of growth per point.

    PYTHONPATH=src python benchmarks/bench_stream_memory.py                    # 1e4, 1e5 points
    PYTHONPATH=src python benchmarks/bench_stream_memory.py --points 1e4 1e5 1e6
    PYTHONPATH=src python benchmarks/bench_stream_memory.py --workers 2        # local worker processes
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile

CHILD = r"""
import json, resource, sys, time
from pathlib import Path
import numpy as np
from periodyn.engine.front import ExecutionOptions, OutputOptions, sweep
from periodyn.examples import pendulum

points, stream, workers, folder = int(sys.argv[1]), sys.argv[2] == "1", int(sys.argv[3]), Path(sys.argv[4])
grid = 10
builder = lambda eccentricity: pendulum(samples=16, eccentricity=eccentricity)
sweep(builder, np.linspace(1.0, 2.0, 4), 4, parameters={"eccentricity": [0.3, 0.5]}, progress=False)

def rss_mib():
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024

base = rss_mib()
omega = np.sqrt(9.81) * np.linspace(0.05, 1.4, points // grid)
start = time.perf_counter()
ds = sweep(builder, omega, 4, stability="magnus", parameters={"eccentricity": np.linspace(0.1, 0.6, grid)},
           workers=workers, out=folder / f"sweep-{points}-{int(stream)}.nc", progress=False,
           execution=ExecutionOptions(eager_workers=workers > 1), output=OutputOptions(stream=stream))
seconds = time.perf_counter() - start
solved = int((ds["status"] == 0).sum())
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({"points": points, "stream": stream, "seconds": seconds, "base": base, "peak": peak,
                  "solved": solved}))
"""


def measure(points: int, stream: bool, workers: int, folder: str) -> dict:
    run = subprocess.run([sys.executable, "-c", CHILD, str(points), str(int(stream)), str(workers), folder],
                         capture_output=True, text=True, check=True)
    return json.loads(run.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", type=float, nargs="+", default=[1e4, 1e5])
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--in-memory-up-to", type=float, default=1e5,
                        help="also run stream=False (in memory) up to this many points")
    args = parser.parse_args()
    print(f"pendulum, 10 eccentricities x n speeds, harmonics 4, samples 16, stability magnus, "
          f"workers {args.workers}; client memory in MiB")
    print(f"{'points':>9} {'results':>9} {'s':>7} {'base':>7} {'peak':>7} {'growth':>7} {'B/point':>8}")
    with tempfile.TemporaryDirectory() as folder:
        for points in map(int, args.points):
            for stream in (True, False):
                if not stream and points > args.in_memory_up_to:
                    continue
                r = measure(points, stream, args.workers, folder)
                growth = r["peak"] - r["base"]
                print(f"{points:>9} {'streamed' if stream else 'memory':>9} {r['seconds']:7.1f} {r['base']:7.0f} "
                      f"{r['peak']:7.0f} {growth:7.0f} {growth * 2**20 / points:8.0f}", flush=True)
                assert r["solved"] == points, r


if __name__ == "__main__":
    main()
