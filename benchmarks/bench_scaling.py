"""Strong scaling of compute-bound sweeps over local worker processes: the Cardan shaft
(sweeps/cardan_shaft.toml) over many speeds, and the slider-crank from elements
(periodyn.examples.slider_crank_rod.slider_crank_model, the model of
sweeps/slider_crank_elements.toml) over a 2-parameter grid (Kelvin-Voigt time constant x
rotary inertia of the rod) times speeds, for 1, 2, ... workers up to the cores present.

Every sweep runs in a fresh process (as a user's ``periodyn sweep`` does; the interpreter's
imports are not timed, the first pool start and kernel loading are), twice for each size, the
faster taken. For each sweep two sizes N are run, and the wall times T(N, w) are fitted by

    T(N, w) = a + N (s + p / w)

(least squares): a the fixed start cost (s), s and p the serial and parallel seconds per
point, serial fraction f = s / (s + p) (Amdahl). Printed per run: points/s, efficiency
T(N, 1) / (w T(N, w)); per sweep: a, f, the fit's predicted efficiency at 16 workers for the
largest N measured and for the issue's size (Cardan shaft 10,000 speeds; the grid at 10x
its points), and the measured pool start (until the first worker process is up). Efficiency
needs idle cores: the load average is printed at start and end.

    PYTHONPATH=src python benchmarks/bench_scaling.py                # sizes for 2 cores
    PYTHONPATH=src python benchmarks/bench_scaling.py --scale 10     # 10x the points
    PYTHONPATH=src python benchmarks/bench_scaling.py --only cardan --scale 20

The sweep file's model is built inside the timed call (as ``periodyn sweep`` does): for the
Cardan shaft that is seconds of fixed cost, so use --scale where the sweep itself is short.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

import numpy as np

CHILD = r"""
import json, sys, time
import numpy as np
from periodyn.engine import backends
from periodyn.engine.front import ExecutionOptions, sweep, sweep_file

kind, points, workers = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
ready = []
record = backends._record_start
def timed(pool, closed):
    ready.append(pool.ready_after)
    record(pool, closed)
backends._record_start = timed
start = time.perf_counter()
if kind == "cardan":
    from periodyn.studies.spec import load_sweep_file
    spec = load_sweep_file(sys.argv[4])
    ds = sweep_file(spec, omega=(0.05, 0.999, points), workers=workers, progress=False)
else:
    from periodyn.examples.slider_crank_rod import slider_crank_model
    from periodyn.model.linearization import omega_split
    def rod(kelvin_voigt, rotary_inertia_per_length):
        return omega_split(slider_crank_model(kelvin_voigt, 2, rotary_inertia_per_length), 64)
    grid = {"kelvin_voigt": [2.4e-5, 4.8e-5, 9.6e-5], "rotary_inertia_per_length": [0.0, 1e-6, 4e-6]}
    ds = sweep(rod, np.linspace(150.0, 300.0, points // 9), 12, 64, "magnus", parameters=grid,
               workers=workers, progress=False)
seconds = time.perf_counter() - start
print(json.dumps({"seconds": seconds, "points": int(ds.attrs["points"]), "backend": ds.attrs["backend"],
                  "ready": ready[0] if ready else None}))
"""

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(kind: str, points: int, workers: int, repeats: int) -> dict:
    best = None
    for _ in range(repeats):
        out = subprocess.run([sys.executable, "-c", CHILD, kind, str(points), str(workers),
                              os.path.join(ROOT, "sweeps", "cardan_shaft.toml")],
                             capture_output=True, text=True, check=True)
        result = json.loads(out.stdout.strip().splitlines()[-1])
        if best is None or result["seconds"] < best["seconds"]:
            best = result
    return best


def fit(rows: list[tuple[int, int, float]]) -> tuple[float, float, float]:
    """(a, s, p) of T = a + N (s + p / w) by least squares over (N, w, T) rows."""
    design = np.array([[1.0, n, n / w] for n, w, _ in rows])
    times = np.array([t for _, _, t in rows])
    (a, s, p), *_ = np.linalg.lstsq(design, times, rcond=None)
    return float(a), float(s), float(p)


def efficiency(a: float, s: float, p: float, n: float, w: int) -> float:
    return (a + n * (s + p)) / (w * (a + n * (s + p / w)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scale", type=float, default=1.0, help="multiply the numbers of points")
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--max-workers", type=int, default=len(os.sched_getaffinity(0)))
    parser.add_argument("--only", choices=("cardan", "slider_crank_grid"), help="run one of the two sweeps")
    args = parser.parse_args()
    cores = args.max_workers
    print(f"cores {len(os.sched_getaffinity(0))}, workers 1..{cores}, load average at start "
          f"{' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    sweeps = {"cardan": ("Cardan shaft, m = 12, p = 64, stability auto; N speeds", (150, 300), 10_000),
              "slider_crank_grid": ("slider-crank from elements, 3 x 3 grid x N/9 speeds, m = 12, p = 64, "
                                    "stability magnus", (9000, 18000), 9 * 4000 * 10)}
    for kind, (title, sizes, issue_size) in sweeps.items():
        if args.only and kind != args.only:
            continue
        print(f"\n{title}")
        print(f"{'N':>7} {'workers':>7} {'s':>8} {'points/s':>9} {'efficiency':>10} {'pool up s':>9}")
        rows = []
        for n in (int(round(size * args.scale)) for size in sizes):
            t1 = None
            for w in range(1, cores + 1):
                r = run(kind, n, w, args.repeats)
                t1 = r["seconds"] if w == 1 else t1
                rows.append((r["points"], w, r["seconds"]))
                ready = f"{r['ready']:9.2f}" if r["ready"] is not None else f"{'-':>9}"
                print(f"{r['points']:>7} {w:>7} {r['seconds']:8.2f} {r['points'] / r['seconds']:9.1f} "
                      f"{t1 / (w * r['seconds']):10.1%} {ready}", flush=True)
        a, s, p = fit(rows)
        largest = max(n for n, _, _ in rows)
        f = s / (s + p) if s + p else float("nan")
        print(f"fit T = a + N (s + p/w): start cost a = {a:.2f} s, serial s = {s * 1e3:.3f} ms/point, "
              f"parallel p = {p * 1e3:.3f} ms/point, serial fraction f = {f:.3%}")
        if s < 0 or p <= 0 or a < 0:
            print("the fit is not physical (a coefficient is negative): the timings are dominated by other load "
                  "or by noise; rerun on idle cores, with --scale for longer sweeps")
            continue
        print(f"predicted efficiency at 16 workers: {efficiency(a, s, p, largest, 16):.1%} at N = {largest}, "
              f"{efficiency(a, s, p, issue_size, 16):.1%} at N = {issue_size} "
              f"(T1 = {a + issue_size * (s + p):.0f} s); Amdahl limit of f alone {1 / (16 * f + 1 - f):.1%}"
              if f > 0 else f"predicted efficiency at 16 workers: {efficiency(a, s, p, largest, 16):.1%} at N = "
              f"{largest}, {efficiency(a, s, p, issue_size, 16):.1%} at N = {issue_size} (fitted f <= 0)")
    print(f"\nload average at end {' '.join(f'{x:.1f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
