"""A large element model swept the way a user sweeps it: ``periodyn.sweep`` with default
options (certified stability, "auto"), 1 worker against all cores, side by side in one run.

Slider-crank with a rod of N beam elements (2 % damping in the first mode, m = 12,
150-300 rad/s), the model built once (its set-up is printed apart); per worker count the
speeds/s of the whole sweep (worker start, chunks, gathering included), the efficiency
against one worker, the methods "auto" took and the largest certified error bound of the
method "reduced", and the cost per speed relative to the first model's at the same worker
count. The sweeps of the models alternate, each repeated ``--repeats`` times, the fastest
taken (on a shared machine the load drifts between runs). BLAS/Numba threads are pinned to
1 in every process.

Run: python benchmarks/bench_large_sweep.py [--elements 8 32] [--speeds 400] [--workers 1 2] [--repeats 3]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from periodyn.engine.front import sweep  # noqa: E402
from periodyn.engine.threads import available_cores  # noqa: E402
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model  # noqa: E402
from periodyn.model.linearization import omega_split  # noqa: E402

M_HARMONICS = 12


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--elements", type=int, nargs="+", default=[8, 32])
    ap.add_argument("--speeds", type=int, default=400)
    ap.add_argument("--workers", type=int, nargs="+", default=[1, available_cores()])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    omega = np.linspace(150.0, 300.0, args.speeds)
    print(f"slider-crank, m = {M_HARMONICS}, {args.speeds} speeds 150-300 rad/s, {available_cores()} cores, "
          f"fastest of {args.repeats}")
    models, setup = {}, {}
    for el in args.elements:
        t0 = time.perf_counter()
        w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=el))
        models[el] = omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=el), 64)
        sweep(models[el], omega[:4], M_HARMONICS, progress=False)  # compile, first ladders, the projections
        setup[el] = time.perf_counter() - t0
    print(f"{'rod el':>6}{'n':>5}{'set-up s':>10}{'workers':>8}{'speeds/s':>10}{'efficiency':>11}"
          f"{'cost':>7}  methods / bound")
    base = {}
    for workers in args.workers:
        best, data = {el: np.inf for el in models}, {}
        for _ in range(args.repeats):
            for el, model in models.items():
                t0 = time.perf_counter()
                data[el] = sweep(model, omega, M_HARMONICS, workers=workers, progress=False)
                best[el] = min(best[el], time.perf_counter() - t0)
        for el, ds in data.items():
            rate = args.speeds / best[el]
            base.setdefault(el, rate)
            method = ds["stability_method"].values
            methods = "/".join(f"{m} {int((method == m).sum())}" for m in dict.fromkeys(method))
            bounds = ds["stability_error_bound"].values
            bound = np.nanmax(bounds) if np.isfinite(bounds).any() else np.nan
            cost = best[el] / best[args.elements[0]]
            print(f"{el:6d}{models[el].n:5d}{setup[el]:10.1f}{workers:8d}{rate:10.3g}"
                  f"{rate / base[el] / workers:11.0%}{cost:6.2f}x  {methods} / {bound:.1e}", flush=True)


if __name__ == "__main__":
    main()
