"""Shooting continuation per point against a plain scipy shooting of the same ODE, side by side.

For each example the periodyn branch ``continuation(..., method="shooting")`` runs first;
then, at every omega of that branch, a plain scipy shooting (a hand-written NumPy
right-hand side with its variational equations, ``solve_ivp`` DOP853 at the same
tolerances rtol 1e-11, atol 1e-12, Newton to the same residual 1e-9) starts from the
previous branch point's state, as the continuation corrector does. Printed: seconds per
point of each, their ratio (the first periodyn run includes loading the model's jitted
kernels from the on-disk cache; the same branch run again is printed beside it), and the
largest multiplier difference between the two.

Examples: Duffing x'' + 0.1 x' + x + 0.5 x^3 = 0.5 cos(w t) over w in 0.5-2.5 (both folds);
the rod pendulum (m = l = 1, eps = 0.1, f = 1) over 1-3 rad/s, whose plain ODE is the
minimal-coordinate equation (m l^2 / 3) phi'' = -m g l/2 cos(phi) - eps phi' + f cos(w t)
while periodyn integrates the index-3 DAE in (x, y, phi) with its two constraints.

Last: cold starts of the Duffing oscillator at omega = 1.02 (from rest; after 200 settling
periods), time and result.

Run: python benchmarks/bench_shooting_core.py [--quick]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

from periodyn.arclength import continuation  # noqa: E402
from periodyn.examples.dae_examples import duffing, rod_pendulum  # noqa: E402

RTOL, ATOL, TOL = 1e-11, 1e-12, 1e-9


def plain_shooting(accel, jac, omega, s0, max_iter=30):
    """Newton on s(T) - s for x'' = accel(t, x, x'); monodromy from the variational
    equations with jac(t, x, x') = (d accel/dx, d accel/dx'). Returns (s, multipliers, iterations)."""
    T = 2 * np.pi / omega

    def rhs(t, y):
        x, v = y[0], y[1]
        kx, kv = jac(t, x, v)
        P = y[2:].reshape(2, 2)
        return np.concatenate([[v, accel(t, x, v)], np.array([P[1], kx * P[0] + kv * P[1]]).ravel()])

    s = np.array(s0, float)
    for it in range(max_iter + 1):
        y = solve_ivp(rhs, (0, T), np.concatenate([s, np.eye(2).ravel()]), method="DOP853", rtol=RTOL, atol=ATOL).y[:, -1]
        R, mono = y[:2] - s, y[2:].reshape(2, 2)
        if np.max(np.abs(R)) <= TOL:
            return s, np.linalg.eigvals(mono), it
        s = s - np.linalg.solve(mono - np.eye(2), R)
    raise RuntimeError(f"plain shooting did not converge at omega={omega}")


def duffing_plain():
    def accel(t, x, v, w=[1.0]):
        return -0.1 * v - x - 0.5 * x ** 3 + 0.5 * np.cos(w[0] * t)

    def jac(t, x, v):
        return -1.0 - 1.5 * x * x, -0.1
    return accel, jac


def rod_plain():
    m, l, eps, f, g = 1.0, 1.0, 0.1, 1.0, 9.81
    inertia = m * l * l / 3

    def accel(t, x, v, w=[1.0]):
        return (-m * g * l / 2 * np.cos(x) - eps * v + f * np.cos(w[0] * t)) / inertia

    def jac(t, x, v):
        return m * g * l / 2 * np.sin(x) / inertia, -eps / inertia
    return accel, jac


def compare(name, system, omega_range, plain, coordinate, ds_max):
    t0 = time.perf_counter()
    br = continuation(system, omega_range, harmonics=7, method="shooting", ds_max=ds_max)
    t_pd = time.perf_counter() - t0
    t0 = time.perf_counter()  # the same branch again: without the first use of the model's jitted kernels
    continuation(system, omega_range, harmonics=7, method="shooting", ds_max=ds_max)
    t_warm = time.perf_counter() - t0
    accel, jac = plain
    solved, diff, t_plain, iters = 0, 0.0, 0.0, 0
    for k in range(1, len(br.omega)):
        prev, sol = br.solutions[k - 1], br.solutions[k]
        s0 = [prev(0.0)[0, coordinate], prev.velocity(0.0)[0, coordinate]]
        accel.__defaults__[0][0] = sol.omega
        t0 = time.perf_counter()
        try:
            s, mu, it = plain_shooting(accel, jac, sol.omega, s0)
        except (RuntimeError, np.linalg.LinAlgError):
            t_plain += time.perf_counter() - t0
            continue
        t_plain += time.perf_counter() - t0
        solved, iters = solved + 1, iters + it
        if abs(s[0] - sol(0.0)[0, coordinate]) < 1e-6:  # the same orbit: compare multipliers
            diff = max(diff, np.max(np.abs(np.sort_complex(mu) - np.sort_complex(sol.multipliers))))
    per_pd, per_warm, per_plain = t_pd / len(br.omega), t_warm / len(br.omega), t_plain / max(solved, 1)
    print(f"{name:14s} points {len(br.omega):4d}  periodyn {per_pd * 1e3:8.1f} ms/point  plain scipy {per_plain * 1e3:8.1f} "
          f"ms/point ({solved} solved, {iters / max(solved, 1):.1f} Newton steps)  ratio {per_pd / per_plain:5.2f}x  "
          f"(second run {per_warm * 1e3:.1f} ms/point, {per_warm / per_plain:4.2f}x)  max |d mu| {diff:.1e}  "
          f"folds {sorted(round(p.omega, 4) for p in br.points('fold'))}")


def cold_starts():
    """Duffing at omega = 1.02 from rest: default start, and 200 settling periods."""
    from periodyn.nonlinear import shooting
    s = duffing(0.05, 0.5, 0.5)
    for label, kw in (("from rest", {}), ("settle 200 periods", {"settle_periods": 200})):
        t0 = time.perf_counter()
        try:
            sol = shooting(s, 1.02, **kw)
            out = f"amplitude {sol.amplitude()[0]:.6f}, residual {sol.residual:.1e}"
        except Exception as exc:  # noqa: BLE001 - the benchmark reports any failure
            out = f"failed: {type(exc).__name__}: {str(exc)[:90]}"
        print(f"cold start duffing w=1.02 {label:20s} {time.perf_counter() - t0:7.2f} s  {out}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="shorter omega ranges")
    args = ap.parse_args()
    compare("duffing", duffing(0.05, 0.5, 0.5), (0.5, 1.2 if args.quick else 2.5), duffing_plain(), 0, 0.2)
    compare("rod pendulum", rod_pendulum(1.0, 1.0, 0.1, 1.0), (1.0, 1.5 if args.quick else 3.0), rod_plain(), 2, 0.2)
    cold_starts()


if __name__ == "__main__":
    main()
