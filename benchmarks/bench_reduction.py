"""Large element models: sweeps on the reduced path, and the full certified Magnus ladder
against the certified reduced method (mean-system modal reduction + Schur correction).

First table, the sweep with default options (:class:`periodyn.speeds.SpeedSolver`,
stability "auto": the method "reduced" with the reduced HB where it is estimated cheaper,
else the full model's ladder) per rod mesh: speeds/s of the whole sweep, the HB's share in
ms per speed (the HB the sweep took and, up to --full-hb-max elements, the full HB on the
same speeds), the stability's share, the methods "auto" took, the largest certified error
bound of "reduced" (the ladder's own error where it took the full ladder is below
STABILITY_TOL), the largest full-HB residual and the set-up (model to first solved speeds,
once per model).

Second table:

Slider-crank with 2 ... 64 (--large: 128) rod elements, 2 % damping in the first mode,
m = 12, 150-300 rad/s, one core (threads pinned for both arms). Per model: speeds/s of
the full ladder (the ladder of "auto", run to certification, budget unlimited; on the
large models only a handful of speeds) and of the reduced method
(:class:`periodyn.stability.reduced.ReducedStability`, speeds it cannot certify with
fewer than n modes are counted as not certified: a sweep hands them to "auto"), the
certified error of log max|mu| of each (largest over the speeds: the ladder's estimate;
the reduced bound, ladder error + 2 |d_lambda| T), the mode counts used, the largest
difference between the two where both ran, and the set-up of the reduced method.

Run: python benchmarks/bench_reduction.py [--speeds 24] [--large] [--full-max 64] [--full-hb-max 32]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model  # noqa: E402
from periodyn.model.linearization import omega_split  # noqa: E402
from periodyn.stability.magnus import MagnusLadder  # noqa: E402
from periodyn.speeds import SpeedSolver  # noqa: E402
from periodyn.stability.reduced import ReducedStability  # noqa: E402

M_HARMONICS = 12
FULL_SPEEDS = {16: 6, 32: 2, 64: 1}  # speeds timed for the full ladder on the large models (128: none)


def scaled_slider_crank(elements: int, samples: int = 64):
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=elements))
    return omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=elements), samples)


def sweep_row(el: int, omegas: np.ndarray, full_hb: bool) -> None:
    """One row of the sweep table (module docstring)."""
    t0 = time.perf_counter()
    model = scaled_slider_crank(el)
    solver = SpeedSolver(model, M_HARMONICS)
    solver.solve_many(omegas[:2])  # jit, first ladders, the per-model projections
    setup = time.perf_counter() - t0
    t0 = time.perf_counter()
    res = solver.solve_many(omegas)
    rate = omegas.size / (time.perf_counter() - t0)
    t0 = time.perf_counter()
    q, residual, message, modes = solver._balance(omegas)
    hb = (time.perf_counter() - t0) / omegas.size
    full = np.nan
    if full_hb:
        some = omegas[:: max(1, omegas.size // 4)]
        solver.balance.solve_many(some[:1], solver.batch_balance)  # the dense terms, the first reference LU
        t0 = time.perf_counter()
        solver.balance.solve_many(some, solver.batch_balance)
        full = (time.perf_counter() - t0) / some.size
    methods = "/".join(f"{name} {int((res.method == name).sum())}" for name in dict.fromkeys(res.method))
    bound = np.nanmax(res.stability_error_bound) if np.isfinite(res.stability_error_bound).any() else np.nan
    print(f"{el:6d}{model.n:5d}{rate:10.3g}{1e3 / rate:10.3g}{hb * 1e3:9.3g}{full * 1e3:10.3g}"
          f"{1e3 / rate - hb * 1e3:10.3g}  {methods:<22}{bound:9.1e}{np.nanmax(res.residual):10.1e}"
          f"{int(modes.max()):>4d}/{int(res.reduced_modes.max()):<4d}{setup:8.1f}", flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--speeds", type=int, default=24)
    ap.add_argument("--large", action="store_true", help="also 128 rod elements")
    ap.add_argument("--full-max", type=int, default=64, help="time the full ladder up to this many rod elements")
    ap.add_argument("--full-hb-max", type=int, default=32, help="time the full HB up to this many rod elements")
    args = ap.parse_args()
    omegas = np.linspace(150.0, 300.0, args.speeds)
    meshes = (2, 4, 8, 16, 32, 64) + ((128,) if args.large else ())
    print(f"sweep, default options (stability 'auto'), slider-crank, m = {M_HARMONICS}, {omegas[0]:g}-{omegas[-1]:g} "
          f"rad/s, {omegas.size} speeds, one core")
    print(f"{'rod el':>6}{'n':>5}{'sp/s':>10}{'ms/speed':>10}{'HB ms':>9}{'full HB':>10}{'stab ms':>10}  "
          f"{'methods':<22}{'bound':>9}{'HB resid':>10}{'k HB/stab':>10}{'set-up s':>9}")
    for el in meshes:
        sweep_row(el, omegas, el <= args.full_hb_max)
    print()
    print(f"slider-crank, m = {M_HARMONICS}, {omegas[0]:g}-{omegas[-1]:g} rad/s, one core")
    print(f"{'rod el':>6}{'n':>5}{'full sp/s':>11}{'(speeds)':>9}{'full err':>10}{'reduced sp/s':>14}{'certified':>10}"
          f"{'bound':>9}{'modes':>8}{'|diff|':>9}{'set-up s':>10}{'ratio':>8}")
    for el in meshes:
        model = scaled_slider_crank(el)
        t0 = time.perf_counter()
        R = ReducedStability(model)
        R.solve(omegas[:1], M_HARMONICS)  # jit, first ladders
        setup = time.perf_counter() - t0
        t0 = time.perf_counter()
        exps, done, reasons, records = R.solve(omegas, M_HARMONICS)
        red_rate = omegas.size / (time.perf_counter() - t0)
        G = exps.real.max(axis=1) * 2 * np.pi / omegas
        bounds = records["stability_error_bound"][done].tolist()
        modes = sorted(set(records["reduced_modes"][done].tolist()))
        count = FULL_SPEEDS.get(el, omegas.size) if el <= min(args.full_max, 64) else 0
        full_rate, full_err, diff = float("nan"), float("nan"), float("nan")
        if count:
            ladder = MagnusLadder(*model._power_spectra[:3])
            ladder.solve(omegas[:1], np.inf)  # jit, first rungs
            w = omegas[np.unique(np.linspace(0, omegas.size - 1, count).round().astype(int))]
            t0 = time.perf_counter()
            est = ladder.solve(w, np.inf)
            full_rate = w.size / (time.perf_counter() - t0)
            full_err = est.error.max()
            Gf = est.exponents.real.max(axis=1) * 2 * np.pi / w
            both = done[np.searchsorted(omegas, w)]
            diff = np.abs(Gf - G[np.searchsorted(omegas, w)])[both].max() if both.any() else np.nan
        print(f"{el:6d}{model.n:5d}{full_rate:11.3g}{count:9d}{full_err:10.1e}{red_rate:14.3g}"
              f"{done.sum():5d}/{omegas.size:<4d}{max(bounds, default=np.nan):9.1e}{'/'.join(map(str, modes)) or '-':>8}"
              f"{diff:9.1e}{setup:10.2f}{red_rate / full_rate if done.all() else np.nan:9.3g}", flush=True)


if __name__ == "__main__":
    main()
