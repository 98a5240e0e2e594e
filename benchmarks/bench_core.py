"""Core benchmark (issue: rheo-linear core), all on one core, measured side by side:

1. sparse-subset Hill (ARPACK shift-invert) vs dense Hill (LAPACK, all eigenvalues) on a
   parametric chain at (n, m) = (20, 20) and (50, 30): time ratio, largest exponent
   difference, stability verdicts;
2. Hill vs the monodromy matrix by direct integration for the same exponents;
3. throughput of a 1000-speed pendulum sweep with stability (speeds per second).

Run: python benchmarks/bench_core.py [--quick]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from scipy.optimize import linear_sum_assignment  # noqa: E402

import periodyn  # noqa: E402
from periodyn.speeds import SpeedSolver  # noqa: E402
from periodyn.examples.chain import parametric_chain  # noqa: E402


def matched_difference(a, b):
    cost = np.abs(a[:, None] - b[None, :])
    i, j = linear_sum_assignment(cost)
    return cost[i, j].max()


def timed(fun, repeat=1):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fun()
        best = min(best, time.perf_counter() - t0)
    return out, best


def hill_sparse_vs_dense(n, m):
    model = parametric_chain(n, samples=4 * m + 8)
    w_max = 2 * np.sqrt(1e4)
    system = model.at(w_max / 6)
    sparse, ts = timed(lambda: periodyn.characteristic_exponents(system, m, "sparse"), repeat=2)
    dense, td = timed(lambda: periodyn.characteristic_exponents(system, m, "dense"))
    diff = matched_difference(sparse.exponents, dense.exponents)
    print(f"  n={n:3d} m={m:3d} Hill size {2 * (2 * m + 1) * n:6d}: sparse {ts:8.3f} s  dense {td:8.3f} s  "
          f"ratio {td / ts:7.1f}x  max |d lambda| {diff:.2e} rad/s  stable sparse/dense {sparse.stable}/{dense.stable}")
    return system, sparse


def hill_vs_monodromy(system, sparse, m):
    mono, tm = timed(lambda: periodyn.characteristic_exponents(system, m, "monodromy"))
    _, ts = timed(lambda: periodyn.characteristic_exponents(system, m, "sparse"))
    diff = matched_difference(sparse.multipliers, mono.multipliers)
    print(f"  n={system.n:3d}: monodromy {tm:8.3f} s  sparse Hill {ts:8.3f} s  ratio {tm / ts:6.1f}x  "
          f"max |d mu| {diff:.2e}")


def pendulum_sweep(count, m, reference, repeat=3):
    """Speeds per second with stability (best of ``repeat``): SpeedSolver.solve_many (the
    sweep path: omega-polynomial blocks built once, stacked LAPACK calls and jitted
    cluster selection per chunk of speeds) and, side by side, the per-speed path
    solve_point(model.at(omega)); convergence in m against ``reference`` (the same sweep
    with m = 16)."""
    model = periodyn.examples.pendulum(samples=36)
    w0 = model.metadata["omega0"]
    omegas = np.linspace(0.1, 1.4, count) * w0
    solver = SpeedSolver(model, m)
    solver.solve_many(omegas[:2])  # warm-up (jit, caches)
    batch, t_solver = timed(lambda: solver.solve_many(omegas), repeat)
    stable_direct, t_direct = timed(lambda: [periodyn.solve_point(model.at(w), m).stable for w in omegas])
    assert list(batch.stable) == stable_direct
    amp_err = np.max(np.abs(batch.amplitude[:, 0] - reference.amplitude[:, 0]) / reference.amplitude[:, 0])
    same = int(np.sum(batch.stable == reference.stable))
    print(f"  {count} speeds, m={m:2d}: SpeedSolver.solve_many {count / t_solver:6.0f} speeds/s, per-speed "
          f"solve_point {count / t_direct:6.0f} speeds/s ({t_direct / t_solver:.0f}x); vs m=16: amplitude rel. "
          f"error {amp_err:.1e}, {same}/{count} same verdicts")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="skip the (n, m) = (50, 30) dense reference")
    args = parser.parse_args()
    print("1. Hill: sparse subset vs dense")
    system, sparse = hill_sparse_vs_dense(20, 20)
    if not args.quick:
        hill_sparse_vs_dense(50, 30)
    print("2. Hill vs monodromy (direct integration)")
    hill_vs_monodromy(system, sparse, 20)
    print("3. Pendulum sweep with stability, one core")
    model = periodyn.examples.pendulum(samples=36)
    reference = SpeedSolver(model, 16).solve_many(np.linspace(0.1, 1.4, 1000) * model.metadata["omega0"])
    for m in (6, 8, 12):
        pendulum_sweep(1000, m, reference)


if __name__ == "__main__":
    main()
