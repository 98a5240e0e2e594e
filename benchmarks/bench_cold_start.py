"""Cold start: a 1000-speed sweep in a fresh process with 1 and with 2 workers; with
``--cold``, install-to-first-result per example kind.

Each run is a new Python process (``import periodyn``, building the model, starting the
worker processes and their fork server, loading the compiled kernels from Numba's
cache, solving); the runs alternate between the worker counts, and the median wall
time of each is printed with the ratio 2 workers / 1 worker (below 1: the second
worker pays for its start). Run ``periodyn warmup`` once before, so that the kernels
are in the cache (a cold cache is the first-install case, not this one).

Compare source trees by running it once per tree with ``PYTHONPATH=<tree>/src``.

``--cold TREE [TREE ...]``: the first result after an install, per example kind (the
first sweep file of each kind run by the ``periodyn`` command over two speeds: a speed
sweep, a rotor's Campbell diagram, a DAE's continuation), each in a fresh process with an
empty Numba cache (NUMBA_CACHE_DIR), no built-model cache and the source tree TREE/src, so nothing is compiled
before; prints the process CPU seconds (all threads, the compile) and wall seconds per
kind and tree, side by side, and the ratio of the CPU seconds to the first tree's.

Run: python benchmarks/bench_cold_start.py [--rounds 3] [--speeds 1000] [--cases pendulum cardan]
     python benchmarks/bench_cold_start.py --cold /path/to/old/tree . [--kinds slider-crank dae]
"""

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

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


#: example kind -> the first thing a user runs with it (run from the tree's root)
FIRST_RESULTS = {
    "pendulum": "main(['sweep', 'sweeps/pendulum.toml', '--omega', '1.0:1.1:2', '--out', OUT, '--workers', '1', '-q'])",
    "slider-crank": "main(['sweep', 'sweeps/slider_crank_elements.toml', '--omega', '200:201:2', '--out', OUT, "
                    "'--workers', '1', '-q'])",
    "cardan": "main(['sweep', 'sweeps/cardan_shaft.toml', '--omega', '300:301:2', '--out', OUT, '--workers', '1', '-q'])",
    "rotor": "main(['sweep', 'sweeps/rotor_campbell.toml', '--omega', '4000:4001:2', '--out', OUT, '-q'])",
    "dae": "main(['sweep', 'sweeps/dae_rod_pendulum.toml', '--omega', '3.5:3.6:2', '--out', OUT, '-q'])",
}
COLD_SCRIPT = """
from periodyn.cli import main
OUT = {out!r}
{call}
"""


def cold_run(tree: Path, kind: str) -> tuple[float, float]:
    """(CPU seconds, wall seconds) of a fresh process computing the kind's first result
    from ``tree`` with an empty Numba cache."""
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as tmp:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(tree / "src"), "PERIODYN_MODEL_CACHE": "off"}
        code = COLD_SCRIPT.format(out=str(Path(tmp) / "first.nc"), call=FIRST_RESULTS[kind])
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], cwd=tree, env=env, check=True, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime, wall


def cold(trees: list[Path], kinds: list[str]) -> None:
    """Install-to-first-result table, trees side by side (module docstring)."""
    print("first result with an empty Numba cache: CPU s / wall s per tree; CPU ratio to the first tree")
    for i, tree in enumerate(trees):
        print(f"  tree {i}: {tree}")
    print(f"{'kind':<14}" + "".join(f"{f'tree {i} CPU':>12}{'wall':>8}" for i in range(len(trees)))
          + "".join(f"{f'{i}/0':>7}" for i in range(1, len(trees))))
    for kind in kinds:
        rows = [cold_run(tree, kind) for tree in trees]
        print(f"{kind:<14}" + "".join(f"{cpu:12.1f}{wall:8.1f}" for cpu, wall in rows)
              + "".join(f"{cpu / rows[0][0]:7.2f}" for cpu, _ in rows[1:]), flush=True)


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
    ap.add_argument("--cold", nargs="+", type=Path, metavar="TREE", help="install-to-first-result per source tree")
    ap.add_argument("--kinds", nargs="+", choices=list(FIRST_RESULTS), default=list(FIRST_RESULTS))
    args = ap.parse_args()
    if args.cold:
        cold([tree.resolve() for tree in args.cold], args.kinds)
        return
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
