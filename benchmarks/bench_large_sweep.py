"""A large element model swept the way a user sweeps it: ``periodyn.sweep`` with default
options (certified stability, "auto"), 1 worker against all cores, side by side in one run.

Slider-crank with a rod of N beam elements (2 % damping in the first mode, m = 12,
150-300 rad/s), the model built once (its set-up is printed apart); per worker count the
speeds/s of the whole sweep (worker start, chunks, gathering included), the efficiency
against one worker, the methods "auto" took and the largest certified error bound of the
method "reduced". BLAS/Numba threads are pinned to 1 in every process.

Run: python benchmarks/bench_large_sweep.py [--elements 8 32] [--speeds 400] [--workers 1 2]
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
    args = ap.parse_args()
    omega = np.linspace(150.0, 300.0, args.speeds)
    print(f"slider-crank, m = {M_HARMONICS}, {args.speeds} speeds 150-300 rad/s, {available_cores()} cores")
    print(f"{'rod el':>6}{'n':>5}{'set-up s':>10}{'workers':>8}{'speeds/s':>10}{'efficiency':>11}  methods / bound")
    for el in args.elements:
        t0 = time.perf_counter()
        w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=el))
        model = omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=el), 64)
        sweep(model, omega[:4], M_HARMONICS, progress=False)  # compile, first ladders, the projections
        setup = time.perf_counter() - t0
        base = None
        for workers in args.workers:
            t0 = time.perf_counter()
            ds = sweep(model, omega, M_HARMONICS, workers=workers, progress=False)
            rate = args.speeds / (time.perf_counter() - t0)
            base = base or rate
            method = ds["stability_method"].values
            methods = "/".join(f"{m} {int((method == m).sum())}" for m in dict.fromkeys(method))
            bound = np.nanmax(ds["stability_error_bound"].values) if np.isfinite(
                ds["stability_error_bound"].values).any() else np.nan
            print(f"{el:6d}{model.n:5d}{setup:10.1f}{workers:8d}{rate:10.3g}{rate / base / workers:11.0%}  "
                  f"{methods} / {bound:.1e}", flush=True)


if __name__ == "__main__":
    main()
