"""Harmonic balance of the slider-crank with 32 rod elements (n = 64, m = 12: N = 1600 real
unknowns), 100 speeds over 150-300 rad/s through its resonances, one core: the GMRES path
(preconditioned with the LU at an earlier speed, :mod:`periodyn.harmonic.batch_balance`) against
the direct dense LU of every speed from the same precomputed terms, measured side by side;
the largest differences of the harmonics and amplitudes relative to each speed's largest,
the residuals, and the LUs the GMRES path took.

Run: python benchmarks/bench_iterative_balance.py [--speeds 100]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import periodyn.harmonic.batch_balance as batch  # noqa: E402
from periodyn.speeds import SpeedSolver  # noqa: E402
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model  # noqa: E402
from periodyn.model.linearization import omega_split  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speeds", type=int, default=100)
    args = ap.parse_args()
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=32))
    model = omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=32), 64)
    w = np.linspace(150.0, 300.0, args.speeds)
    solvers, results, seconds = {}, {}, {}
    for arm, smallest in (("gmres", batch.ITERATIVE_MIN), ("direct", 10**9)):
        batch.ITERATIVE_MIN = smallest
        solvers[arm] = solver = SpeedSolver(model, 12, stability=False)
        solver.solve_many(w[:1])  # terms, jit
        solver.balance.references.clear()
        solver.balance.factorizations = 0
        t0 = time.perf_counter()
        results[arm] = solver.solve_many(w)
        seconds[arm] = time.perf_counter() - t0
    it, d = results["gmres"], results["direct"]
    scale = np.abs(d.output_harmonics).max(axis=(1, 2))
    err = np.abs(it.output_harmonics - d.output_harmonics).max(axis=(1, 2)) / scale
    amp = np.abs(it.amplitude - d.amplitude).max(axis=1) / np.abs(d.amplitude).max(axis=1)
    print(f"N = {solvers['gmres'].pattern.size}, {w.size} speeds: GMRES {seconds['gmres']:.2f} s "
          f"({solvers['gmres'].balance.factorizations} LUs), direct {seconds['direct']:.2f} s, "
          f"direct/GMRES {seconds['direct'] / seconds['gmres']:.2f}")
    print(f"largest relative difference: harmonics {err.max():.2e} (at {w[err.argmax()]:.1f} rad/s), "
          f"amplitudes {amp.max():.2e}")
    print(f"largest relative residual: GMRES {np.nanmax(it.residual):.2e}, direct {np.nanmax(d.residual):.2e}; "
          f"failed points {int((it.message != '').sum())} / {int((d.message != '').sum())}")


if __name__ == "__main__":
    main()
