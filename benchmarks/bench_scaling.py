"""Strong scaling of compute-bound sweeps over local worker processes: the Cardan shaft
(sweeps/cardan_shaft.toml) over many speeds, and the slider-crank from elements
(periodyn.examples.slider_crank_rod.slider_crank_model, the model of
sweeps/slider_crank_elements.toml) over a 2-parameter grid (Kelvin-Voigt time constant x
rotary inertia of the rod) times speeds, for 1, 2, ... workers up to the cores present.

Two predictions of the efficiency at 16 workers are printed, from

- FITTED: the wall times fitted by T(N, w) = a + N (s + p / w) (below). On a few cores
  shared with other work the fit cannot tell serial work from contention for the cores:
  both make T shrink less than 1/w, so both land in s.
- MEASURED: the serial parts timed directly in the sweep's process: the wall time outside
  the chunk loop (set-up: sweep file, model building, chunking; finish: merging the
  chunks, writing the result file), the wall time from the loop's start until the first
  worker was up (counted as serial although the calling process solves chunks meanwhile)
  and the calling process's CPU time in the loop outside solving (collecting, progress,
  checkpoints, feeding the pool; time.process_time, so a loaded machine does not inflate
  it). Set-up and finish are taken as CPU time as well (they compute, they do not wait): the
  finish and the loop's CPU outside solving are fitted by c + N s over the sizes;
  a = c + the set-up + the wall time until the first worker was up; p is the solving CPU
  time per point of the one-worker runs. A second MEASURED line counts the loop's CPU as
  work the cores share (it runs while the workers solve: with w workers on w cores it
  takes CPU from them, it does not hold them up) and only the finish as serial.
  "1st chunk s" is the wall time from the loop's start until the first chunk came back
  (a worker's first chunk also loads the solver's kernels: not counted in a).

Every sweep runs in a fresh process writing its result file (as a user's ``periodyn sweep`` does; the interpreter's
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
The Cardan table is printed three times (``--model-cache all``): with the model built in
every run (cold: a file's first sweep, PERIODYN_MODEL_CACHE=off), read from the built-model
cache (warm: a file's later sweeps, :func:`periodyn.studies.cache.cached_model`; the cache
filled once before the timed runs), and built in every run by a process forked from a warm
server (served: ``periodyn serve start sweeps/cardan_shaft.toml``, :mod:`periodyn.engine.server`:
imports done and the kernels loaded, the model not cached; each run's client is a fresh
process that hands the run to the server, and its timing is that of the forked process).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

CHILD = r"""
import json, os, sys, tempfile, time
import numpy as np
from periodyn.engine import backends
from periodyn.engine.job import Job
from periodyn.engine.front import ExecutionOptions, sweep, sweep_file

kind, points, workers = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
marks = {"solve_cpu": 0.0, "ready": None, "up_at": None}
solve = Job.solve
def timed_solve(self, indices):  # this process's solves (a forked worker's count in its own copy of marks)
    cpu = time.process_time()
    try:
        return solve(self, indices)
    finally:
        marks["solve_cpu"] += time.process_time() - cpu
Job.solve = timed_solve
record = backends._record_start
def timed_record(pool, closed):
    if pool.ready_after is not None:
        marks["ready"], marks["up_at"] = pool.ready_after, pool.created + pool.ready_after
    record(pool, closed)
backends._record_start = timed_record
def timed_backend(run):
    def timed(job, chunks, workers, execution):
        marks["loop_start"], marks["loop_start_cpu"] = time.perf_counter(), time.process_time()
        for chunk in run(job, chunks, workers, execution):  # the sweep's work between chunks counts too
            marks.setdefault("first_result", time.perf_counter())
            yield chunk
        marks["loop_end"], marks["loop_end_cpu"] = time.perf_counter(), time.process_time()
    return timed
for name in ("serial", "processes"):
    backends.BACKENDS[name] = timed_backend(backends.BACKENDS[name])
out = os.path.join(tempfile.mkdtemp(prefix="bench-scaling-"), "result.nc")  # written, as periodyn sweep does
start, start_cpu = time.perf_counter(), time.process_time()
if kind == "cardan":
    from periodyn.studies.spec import load_sweep_file
    spec = load_sweep_file(sys.argv[4])
    ds = sweep_file(spec, omega=(0.05, 0.999, points), workers=workers, progress=False, out=out)
else:
    from periodyn.examples.slider_crank_rod import slider_crank_model
    from periodyn.model.linearization import omega_split
    def rod(kelvin_voigt, rotary_inertia_per_length):
        return omega_split(slider_crank_model(kelvin_voigt, 2, rotary_inertia_per_length), 64)
    grid = {"kelvin_voigt": [2.4e-5, 4.8e-5, 9.6e-5], "rotary_inertia_per_length": [0.0, 1e-6, 4e-6]}
    ds = sweep(rod, np.linspace(150.0, 300.0, points // 9), 12, 64, "magnus", parameters=grid,
               workers=workers, progress=False, out=out)
end, end_cpu = time.perf_counter(), time.process_time()
window = marks["up_at"] - marks["loop_start"] if marks["up_at"] is not None else None
print(json.dumps({"seconds": end - start, "points": int(ds.attrs["points"]), "backend": ds.attrs["backend"],
                  "ready": marks["ready"], "window": window, "setup": marks["loop_start"] - start,
                  "first_result": marks["first_result"] - marks["loop_start"],
                  "finish": end - marks["loop_end"], "setup_cpu": marks["loop_start_cpu"] - start_cpu,
                  "finish_cpu": end_cpu - marks["loop_end_cpu"], "solve_cpu": marks["solve_cpu"],
                  "overhead_cpu": marks["loop_end_cpu"] - marks["loop_start_cpu"] - marks["solve_cpu"]}))
"""

#: the warm server of the "served" runs: `periodyn serve run sweeps/cardan_shaft.toml` whose command is CHILD
HOST = r"""
import sys
from pathlib import Path
from periodyn.cli import _preload
from periodyn.engine.server import serve

path, child, toml = Path(sys.argv[1]), sys.argv[2], sys.argv[3]

def command(argv):
    sys.argv = ["bench-child", *argv]
    exec(compile(child, "bench-child", "exec"), {"__name__": "__main__"})
    return 0

serve(command, idle=600.0, path=path, preload=lambda: _preload([toml]), ready=lambda path: print("ready", flush=True))
"""
CLIENT = ("import sys; from pathlib import Path; from periodyn.engine.server import delegate; "
          "code = delegate(sys.argv[2:], Path(sys.argv[1])); sys.exit(99 if code is None else code)")
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CARDAN = os.path.join(ROOT, "sweeps", "cardan_shaft.toml")
CACHE_MODES = {"cold": "built in each run (PERIODYN_MODEL_CACHE=off)",
               "warm": "read from the built-model cache (a file's second and later sweeps)",
               "served": "built in each run, by a process forked from a warm server (periodyn serve)"}


def run(kind: str, points: int, workers: int, repeats: int, env: dict | None = None,
        served: str | None = None) -> dict:
    """The fastest of ``repeats`` runs of CHILD, each in a fresh process, or, with ``served``
    (a socket path), in a process forked from that server."""
    best = None
    head = [sys.executable, "-c", CHILD] if served is None else [sys.executable, "-c", CLIENT, served]
    for _ in range(repeats):
        out = subprocess.run(head + [kind, str(points), str(workers), CARDAN],
                             capture_output=True, text=True, check=True, env={**os.environ, **(env or {})})
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


def measured(runs: list[dict], pipeline: bool = False) -> tuple[float, float, float, str] | None:
    """(a, s, p, how) measured directly, not fitted to wall times, from the runs with worker
    processes: the calling process's CPU seconds in the chunk loop outside solving (collecting,
    progress, checkpoints, feeding the pool, loading the result writer) plus its finish (merging,
    writing the file), fitted by c + N s over their sizes (with one size or a negative fit, all of
    it counted per point at the largest N: conservative); a = c + the mean set-up CPU seconds +
    the mean wall time until the first worker was up; p the solving CPU seconds per point of the
    one-worker runs. ``pipeline``: the loop's CPU (spent while the workers solve) counted as
    work shared by the cores (added to p) and only the finish fitted by c + N s."""
    pooled = [r for r in runs if r["backend"] == "processes" and r["window"] is not None]
    single = [r for r in runs if r["workers"] == 1]
    if not pooled or not single:
        return None
    late = np.array([r["finish_cpu"] + (0.0 if pipeline else r["overhead_cpu"]) for r in pooled])
    n = np.array([r["points"] for r in pooled], dtype=float)
    fixed = float(np.mean([r["setup_cpu"] + r["window"] for r in pooled]))
    p = float(np.mean([r["solve_cpu"] / r["points"] for r in single]))
    if pipeline:
        largest = [r for r in pooled if r["points"] == max(n)]
        p += float(np.mean([r["overhead_cpu"] / r["points"] for r in largest]))
    if len(set(n)) > 1:
        (c, s), *_ = np.linalg.lstsq(np.stack([np.ones_like(n), n], axis=1), late, rcond=None)
        if s >= 0 and c >= 0:
            return fixed + float(c), float(s), p, "fitted over N"
    i = int(np.argmax(n))
    return fixed, late[i] / n[i], p, "all counted per point at the largest N (conservative)"


def efficiency(a: float, s: float, p: float, n: float, w: int) -> float:
    return (a + n * (s + p)) / (w * (a + n * (s + p / w)))


def report(kind: str, title: str, sizes: tuple, issue_size: int, cores: int, args, env: dict,
           served: str | None = None) -> None:
    """The table of one sweep over the sizes and worker counts, the fit and the predictions."""
    print(f"\n{title}")
    print(f"{'N':>7} {'workers':>7} {'s':>8} {'points/s':>9} {'efficiency':>10} {'pool up s':>9} "
          f"{'set-up s':>8} {'(CPU)':>6} {'first up s':>10} {'1st chunk s':>11} {'finish s':>8} {'(CPU)':>6} "
          f"{'loop CPU ms/pt':>14}")
    rows, runs = [], []
    for n in (int(round(size * args.scale)) for size in sizes):
        t1 = None
        for w in range(1, cores + 1):
            r = run(kind, n, w, args.repeats, env, served)
            r["workers"] = w
            t1 = r["seconds"] if w == 1 else t1
            rows.append((r["points"], w, r["seconds"]))
            runs.append(r)
            ready = f"{r['ready']:9.2f}" if r["ready"] is not None else f"{'-':>9}"
            window = f"{r['window']:10.2f}" if r["window"] is not None else f"{'-':>10}"
            print(f"{r['points']:>7} {w:>7} {r['seconds']:8.2f} {r['points'] / r['seconds']:9.1f} "
                  f"{t1 / (w * r['seconds']):10.1%} {ready} {r['setup']:8.2f} {r['setup_cpu']:6.2f} {window} "
                  f"{r['first_result']:11.2f} "
                  f"{r['finish']:8.2f} {r['finish_cpu']:6.2f} {1e3 * r['overhead_cpu'] / r['points']:14.4f}",
                  flush=True)
    a, s, p = fit(rows)
    largest = max(n for n, _, _ in rows)
    f = s / (s + p) if s + p else float("nan")
    print(f"FITTED to wall times, T = a + N (s + p/w): start cost a = {a:.2f} s, serial s = {s * 1e3:.3f} "
          f"ms/point, parallel p = {p * 1e3:.3f} ms/point, serial fraction f = {f:.3%}")
    if s < 0 or p <= 0 or a < 0:
        print("  the fit is not physical (a coefficient is negative): the timings are dominated by other load "
              "or by noise; rerun on idle cores, with --scale for longer sweeps")
    else:
        print(f"  predicted efficiency at 16 workers: {efficiency(a, s, p, largest, 16):.1%} at N = {largest}, "
              f"{efficiency(a, s, p, issue_size, 16):.1%} at N = {issue_size} "
              f"(T1 = {a + issue_size * (s + p):.0f} s)")
    print(f"  (with {cores} workers on {cores} cores, and other load, the fitted s also holds the contention "
          "of the processes for the cores, not only serial work)")
    direct = measured(runs)
    if direct is None:
        print("MEASURED: needs runs with worker processes at two sizes and a one-worker run")
        return
    for pipeline, (am, sm, pm, how) in ((False, direct), (True, measured(runs, pipeline=True))):
        if not pipeline:
            print(f"MEASURED directly (serial: the calling process's CPU outside solving in the loop and the "
                  f"finish, {how}; a also holds the set-up CPU and the wall time until the first worker was up; "
                  f"p: the one-worker runs' solving CPU): start cost a = {am:.2f} s, serial s = {sm * 1e3:.4f} "
                  f"ms/point, parallel p = {pm * 1e3:.3f} ms/point, serial fraction f = {sm / (sm + pm):.3%}")
        else:
            print(f"MEASURED, the loop's CPU (spent while the workers solve) counted as work the cores share "
                  f"(in p), serial: the finish ({how}): a = {am:.2f} s, s = {sm * 1e3:.4f} ms/point, "
                  f"p = {pm * 1e3:.3f} ms/point, f = {sm / (sm + pm):.3%}")
        print(f"  predicted efficiency at 16 workers: {efficiency(am, sm, pm, largest, 16):.1%} at N = {largest}, "
              f"{efficiency(am, sm, pm, issue_size, 16):.1%} at N = {issue_size} (T1 = "
              f"{am + issue_size * (sm + pm):.0f} s); assumes the workers solve at the one-worker rate "
              "(idle cores, no memory-bandwidth limit)")
    pooled = [r for r in runs if r["backend"] == "processes"]
    loop = max(pooled, key=lambda r: (r["points"], r["workers"]))
    per_point = loop["overhead_cpu"] / loop["points"]
    print(f"  the loop CPU ({per_point * 1e3:.4f} ms/point at N = {loop['points']}) runs while the workers solve: "
          f"counted as serial in the first MEASURED line (an upper bound); as a pipeline it caps the sweep at "
          f"{1 / per_point:.0f} points/s, {pm / per_point:.0f} workers' worth")


@contextlib.contextmanager
def warm_server(start: bool, folder: str):
    """The socket path of a warm server of CHILD in ``folder`` (None unless ``start``), stopped after."""
    if not start:
        yield None
        return
    path = os.path.join(folder, "bench.sock")
    host = subprocess.Popen([sys.executable, "-c", HOST, path, CHILD, CARDAN], stdout=subprocess.PIPE, text=True)
    try:
        if host.stdout.readline().strip() != "ready":
            raise RuntimeError("the benchmark's warm server did not start")
        yield path
    finally:
        from periodyn.engine.server import stop

        stop(Path(path))
        host.wait(60)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scale", type=float, default=1.0, help="multiply the numbers of points")
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--max-workers", type=int, default=len(os.sched_getaffinity(0)))
    parser.add_argument("--only", choices=("cardan", "slider_crank_grid"), help="run one of the two sweeps")
    parser.add_argument("--model-cache", choices=("cold", "warm", "served", "all"), default="all",
                        help="the Cardan sweep file's model built in each run (cold), read from the built-model "
                             "cache (warm), built in each run by a process forked from a warm server (served), "
                             "or all three tables")
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
        modes = tuple(CACHE_MODES) if args.model_cache == "all" else (args.model_cache,)
        for mode in modes if kind == "cardan" else ("cold",):  # a grid's models are built in the workers
            with tempfile.TemporaryDirectory(prefix="bench-model-cache-") as folder:
                env = {"PERIODYN_CACHE_DIR": folder} if mode == "warm" else {"PERIODYN_MODEL_CACHE": "off"}
                if mode == "warm":
                    run(kind, 10, 1, 1, env)  # the model built once into the cache (not timed)
                with warm_server(mode == "served", folder) as served:
                    report(kind, f"{title}; model {CACHE_MODES[mode]}" if kind == "cardan" else title, sizes,
                           issue_size, cores, args, env, served)
    print(f"\nload average at end {' '.join(f'{x:.1f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
