"""The kernels' LLVM optimization level: compile CPU and run time at -O1 (periodyn's level,
:mod:`periodyn.kernels.optimization`) against -O3 (Numba's default), side by side.

Per level a fresh process with an empty Numba cache (NUMBA_CACHE_DIR) runs each workload
once (cold), and a second fresh process on the now filled cache runs each ``--repeats``
times (warm, best CPU seconds: what running it costs, as every later run sees it); the
cold CPU seconds less the warm ones are what compiling it cost. -O3 is selected by
NUMBA_OPT=3, which periodyn leaves alone. Workloads, each after the ones before it (so a
kernel shared with an earlier one is not compiled again):

- pendulum: the elliptic pendulum, 2,000 speeds with stability (speed solver kernels);
- slider-crank: rod of 8 beam elements, model linearized and 100 speeds with the Magnus
  ladder (mechanism kernels, ladder);
- cardan: the Cardan shaft linearized and 100 speeds (spatial element kernels);
- shooting: the elliptic pendulum's non-linear element model by implicit shooting;
- ihb: the rod pendulum DAE by IHB.

BLAS/Numba threads are pinned to 1. Run: python benchmarks/bench_opt_level.py [--repeats 3]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

CHILD = r"""
import json, os, sys, time, warnings
warnings.simplefilter("ignore")
import numpy as np
import periodyn
from periodyn.examples import cardan_shaft, pendulum, rod_pendulum
from periodyn.examples.elliptic_pendulum import elliptic_pendulum_model
from periodyn.examples.slider_crank_rod import slider_crank_model
from periodyn.kernels.optimization import kernel_opt_level
from periodyn.model.linearization import omega_split
from periodyn.nonlinear import ihb, shooting

def slider_crank():
    model = omega_split(slider_crank_model(1e-5, rod_elements=8), 64)
    periodyn.sweep(model, np.linspace(150.0, 300.0, 100), 12, stability="magnus", progress=False)

WORKLOADS = {
    "pendulum": lambda: periodyn.sweep(pendulum(samples=64), np.linspace(0.05, 1.4, 2000) * 3.1321, 10,
                                       progress=False),
    "slider-crank": slider_crank,
    "cardan": lambda: periodyn.sweep(cardan_shaft(), np.linspace(0.2, 0.99, 100) * 766.0, 12, progress=False),
    "shooting": lambda: shooting(elliptic_pendulum_model(), 0.8 * np.sqrt(9.81), integrator="implicit"),
    "ihb": lambda: ihb(rod_pendulum(), 3.6, 8),
}
out = {"level": kernel_opt_level()}
for name, work in WORKLOADS.items():
    seconds = []
    for _ in range(int(sys.argv[1])):
        c = time.process_time(); work(); seconds.append(time.process_time() - c)
    out[name] = min(seconds)
print(json.dumps(out))
"""


def run(level: int, repeats: int) -> dict:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1",
               NUMBA_NUM_THREADS="1")
    env.pop("NUMBA_OPT", None)
    if level != 1:
        env["NUMBA_OPT"] = str(level)
    runs = []
    with tempfile.TemporaryDirectory() as cache:
        env["NUMBA_CACHE_DIR"] = cache
        env["PERIODYN_MODEL_CACHE"] = "off"  # every run builds its models (the workloads time the kernels)
        for times in (1, repeats):  # cold, then warm
            done = subprocess.run([sys.executable, "-c", CHILD, str(times)], env=env, capture_output=True, text=True)
            if done.returncode:
                sys.exit(f"level {level} failed:\n{done.stderr[-3000:]}")
            runs.append(json.loads(done.stdout.strip().splitlines()[-1]))
    cold, warm = runs
    return {name: (cold[name] - warm[name], warm[name]) if name != "level" else warm[name] for name in warm}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    o1, o3 = run(1, args.repeats), run(3, args.repeats)
    assert o1["level"] == 1 and o3["level"] == 3, (o1["level"], o3["level"])
    print(f"{'workload':<14}{'compile -O1 s':>14}{'-O3 s':>9}{'ratio':>7}{'run -O1 s':>11}{'-O3 s':>9}{'ratio':>7}")
    total1 = total3 = 0.0
    for name in (k for k in o1 if k != "level"):
        (c1, r1), (c3, r3) = o1[name], o3[name]
        total1, total3 = total1 + c1, total3 + c3
        print(f"{name:<14}{c1:>14.1f}{c3:>9.1f}{c3 / c1:>7.2f}{r1:>11.3f}{r3:>9.3f}{r3 / r1:>7.2f}")
    print(f"{'all':<14}{total1:>14.1f}{total3:>9.1f}{total3 / total1:>7.2f}")
    print("ratio = -O3 / -O1 (compile: above 1, -O1 compiles faster; run: below 1, -O3 runs faster)")


if __name__ == "__main__":
    main()
