"""Sweep throughput of the issue targets, speeds per second, for one or more source trees
measured side by side in one run: ``periodyn.sweep`` with default options (m = 12, the
models' 64 samples, stability by the default method, and without stability) on 1 and 2
worker processes, for

- the pendulum, eq. (29), 1000 speeds over 0.002-1.4 omega0 (target with stability: 5,000/s on 2 cores);
- the slider-crank, 2 rod elements, 2 % damping, 1000 speeds over 150-300 rad/s (1,000/s);
- the slider-crank with 32 rod elements, ``--x32-speeds`` speeds over 150-300 rad/s (20/s);
- the Cardan shaft, 1000 speeds over 0.001-0.999 omega_b (1,000/s).

Every tree runs in its own Python processes (``PYTHONPATH=<tree>``), the trees alternating
round by round, with one BLAS/Numba thread per process; each process warms up (compiles,
starts its worker pool) before timing. The best of ``--rounds`` is printed per tree, with
the ratio of each tree to the first. Compare with the previous main:

    python benchmarks/bench_throughput.py --trees /work/main/src src

Run: python benchmarks/bench_throughput.py [--trees SRC ...] [--rounds 2] [--cases ...] [--scale 1.0]
"""

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

THREADS = {v: "1" for v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS")}
CASES = ("pendulum", "slider-crank", "slider-crank x32", "cardan")
TARGETS = {"pendulum": 5000, "slider-crank": 1000, "slider-crank x32": 20, "cardan": 1000}


def build(case: str, speeds: int):
    """(model, speeds rad/s) of a case, built with the periodyn on sys.path."""
    import numpy as np

    import periodyn

    if case == "pendulum":
        model = periodyn.examples.pendulum(samples=64)
        return model, np.linspace(0.002, 1.4, speeds) * model.metadata["omega0"]
    if case == "slider-crank":
        return periodyn.examples.slider_crank(damping=0.02), np.linspace(150.0, 300.0, speeds)
    if case == "slider-crank x32":
        from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
        from periodyn.model.linearization import omega_split

        w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=32))
        return omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=32), 64), np.linspace(150.0, 300.0, speeds)
    model = periodyn.examples.cardan_shaft()
    return model, np.linspace(0.001, 0.999, speeds) * model.metadata["omega_b"]


def child(cases: list[str], speeds: dict[str, int]) -> None:
    """Time every case in this process; one JSON line per sweep on stdout."""
    import periodyn

    try:  # warm-ups start the worker pool (and its fork server) even for their few speeds
        from periodyn.engine.front import ExecutionOptions

        try:
            warm = {"execution": ExecutionOptions(chunk_size=1, eager_workers=True)}
        except TypeError:  # a tree whose workers always start
            warm = {"execution": ExecutionOptions(chunk_size=1)}
    except ImportError:  # a tree before the option objects (its workers always start)
        warm = {"chunk_size": 1}
    for case in cases:
        model, omega = build(case, speeds[case])
        for stability in (True, False):
            for workers in (1, 2):
                periodyn.sweep(model, omega[:8], 12, stability=stability, workers=workers, progress=False, **warm)
                t0 = time.perf_counter()
                ds = periodyn.sweep(model, omega, 12, stability=stability, workers=workers, progress=False)
                seconds = time.perf_counter() - t0
                print(json.dumps({"case": case, "stability": stability, "workers": workers, "speeds": omega.size,
                                  "seconds": seconds, "failed": int(ds.attrs["failed_points"]),
                                  "methods": str(ds.attrs.get("stability_methods", "")).split(";")[0]}), flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trees", nargs="+", default=[str(Path(__file__).resolve().parents[1] / "src")],
                    help="source trees (each put first on PYTHONPATH), e.g. /work/main/src src")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES))
    ap.add_argument("--scale", type=float, default=1.0, help="fraction of the speeds (1000, x32: --x32-speeds)")
    ap.add_argument("--x32-speeds", type=int, default=100)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    speeds = {c: max(8, round((args.x32_speeds if c == "slider-crank x32" else 1000) * args.scale)) for c in CASES}
    if args.child:
        child(args.cases, speeds)
        return
    trees = [str(Path(t).resolve()) for t in args.trees]
    best: dict[tuple, dict] = {}
    print(f"load average at start: {os.getloadavg()[0]:.2f} (2 idle cores needed for clean timings)", flush=True)
    for _ in range(args.rounds):
        for tree in trees:  # alternating, so both trees see the same load
            env = {**os.environ, **THREADS, "PYTHONPATH": tree}
            cmd = [sys.executable, __file__, "--child", "--cases", *args.cases, "--scale", str(args.scale),
                   "--x32-speeds", str(args.x32_speeds)]
            out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True).stdout
            for line in out.splitlines():
                row = json.loads(line)
                key = (tree, row["case"], row["stability"], row["workers"])
                if key not in best or row["seconds"] < best[key]["seconds"]:
                    best[key] = row
    print(f"{'case':<18}{'stability':<11}{'workers':>7}{'speeds':>7}" + "".join(f"{Path(t).parent.name + '/' + Path(t).name:>24}" for t in trees)
          + ("   ratio to first" if len(trees) > 1 else "") + "   target (with stability)")
    for case in args.cases:
        for stability in (True, False):
            for workers in (1, 2):
                rows = [best[(t, case, stability, workers)] for t in trees]
                rates = [r["speeds"] / r["seconds"] for r in rows]
                ratio = "".join(f"{r / rates[0]:7.2f}x" for r in rates[1:])
                target = f"{TARGETS[case]}/s on 2" if stability and workers == 2 else ""
                print(f"{case:<18}{'on' if stability else 'off':<11}{workers:>7}{rows[0]['speeds']:>7}"
                      + "".join(f"{r:>13.1f} speeds/s" for r in rates) + f"   {ratio:<14}  {target}"
                      + ("   FAILED POINTS " + str([r["failed"] for r in rows]) if any(r["failed"] for r in rows) else ""),
                      flush=True)
    print(f"load average at end: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
