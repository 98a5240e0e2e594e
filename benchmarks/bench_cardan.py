"""Cardan drive shaft (Schwab & Meijaard 2001, section 4.4): a 1000-speed sweep over
0 < omega/omega_b < 1 with stability, on 2 worker processes, by the default method
("auto"), against dense Hill, against monodromy integration (DOP853 of the variational
equations, method="monodromy") and against the fixed-step 4th-order Magnus monodromy
(method="magnus", 128 steps per period), measured side by side in one run, each
arm with one BLAS/Numba thread per process. A slow arm runs on an evenly spread subset
of the speeds (--subset) and its rate is speeds per second of that subset. The paper
needed about 1 s per speed for the periodic solution and about 1 min per speed for the
stability.

Run: python benchmarks/bench_cardan.py [--speeds 1000] [--workers 2] [--subset 100]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import periodyn  # noqa: E402


def timed_sweep(model, omega, method, workers, harmonics):
    """(speeds per second, dataset) of one sweep with stability."""
    t0 = time.perf_counter()
    data = periodyn.sweep(model, omega, harmonics, stability=method, workers=workers, progress=False)
    return omega.size / (time.perf_counter() - t0), data


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speeds", type=int, default=1000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--subset", type=int, default=50, help="speeds for the dense and monodromy arms")
    ap.add_argument("--harmonics", type=int, default=12)
    args = ap.parse_args()
    model = periodyn.examples.cardan_shaft()
    wb = model.metadata["omega_b"]
    omega = np.linspace(0.001, 0.999, args.speeds) * wb
    subset = omega[np.linspace(0, omega.size - 1, min(args.subset, omega.size)).astype(int)]
    m = args.harmonics
    # warm-up: compile and start the workers' imports once before timing
    for method in ("auto", "magnus", "dense", "monodromy"):
        periodyn.sweep(model, omega[:2], m, stability=method, progress=False)
    rates, data = {}, {}
    for name, speeds in (("auto", omega), ("magnus", omega), ("dense", subset), ("monodromy", subset)):
        rates[name], data[name] = timed_sweep(model, speeds, name, args.workers, m)
    auto = data["auto"].sel(omega=subset)
    agree = {k: int((auto["stable"].values == data[k].sel(omega=subset)["stable"].values).sum())
             for k in ("magnus", "dense", "monodromy")}
    unstable = auto["stable"].values == 0
    print(f"Cardan shaft: n = {model.n} dynamic coordinates, m = {m} harmonics, {model.samples} samples, "
          f"{args.workers} workers")
    print(f"{'method':<12}{'speeds':>8}{'speeds/s':>12}{'auto x':>10}{'same verdict':>14}")
    for name in rates:
        count = data[name]["omega"].size
        same = "-" if name == "auto" else f"{agree[name]}/{subset.size}"
        print(f"{name:<12}{count:8d}{rates[name]:12.1f}{rates['auto'] / rates[name]:10.1f}{same:>14}")
    full = data["auto"]
    used = full["stability_method"].values
    chosen, counts = np.unique(used, return_counts=True)
    top = {c: full["omega"].values[used == c].max() / wb for c in chosen}
    print("auto chose: " + ", ".join(f"{c} at {k} speeds (up to omega/omega_b = {top[c]:.3f})"
                                     for c, k in zip(chosen, counts)))
    zones = full["omega"].values[full["stable"].values == 0] / wb
    print(f"auto: {int((full['stable'].values == 0).sum())} unstable speeds, omega/omega_b in "
          f"[{zones.min():.3f}, {zones.max():.3f}]; {int(unstable.sum())} of the subset" if zones.size else
          "auto: no unstable speed")
    period = 2 * np.pi / subset
    certified = certified_errors(model, subset, m)
    magnus = auto["stability_method"].values == "magnus"
    for name in ("dense", "monodromy"):
        diff = np.abs(auto["max_real_exponent"].values - data[name]["max_real_exponent"].values)
        i = int(np.nanargmax(diff))
        print(f"max |Re lambda| difference auto - {name} on the subset: {diff[i]:.2e} 1/s (growth per period "
              f"{diff[i] * period[i]:.1e}) at omega/omega_b = {subset[i] / wb:.3f}; largest growth difference "
              f"{np.nanmax(diff * period):.1e}")
        over = magnus & (diff * period > certified)
        print(f"  at the {int(magnus.sum())} Magnus speeds of the subset: growth difference / certified error "
              f"at most {np.nanmax(diff[magnus] * period[magnus] / certified[magnus]):.2f}; "
              f"{int(over.sum())} beyond the certified error")


def certified_errors(model, speeds, m):
    """The Magnus ladder's certified error of log max|mu| (S,) at speeds (as "auto" runs it)."""
    from periodyn.speeds import SpeedSolver
    from periodyn.stability.methods import HILL_TIME_FACTOR

    solver = SpeedSolver(model, m)
    seconds = np.array([c for _, _, c in solver.hill_methods(speeds)])
    return solver.ladder.solve(speeds, seconds * HILL_TIME_FACTOR).error


if __name__ == "__main__":
    main()
