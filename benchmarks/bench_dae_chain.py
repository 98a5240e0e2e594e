"""41-body slider-chain pendulum (122 coordinates, 81 multipliers): EGA-IHB continuation
vs numerical integration to steady state, side by side in one run (one core).

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python benchmarks/bench_dae_chain.py [--harmonics 10]
        [--curve-only] [--profile N]

Before/after in one command (the same script on the previous tree and on this one):

    for src in /work/main/src src /work/main/src src; do OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1 \
        PYTHONPATH=$src python benchmarks/bench_dae_chain.py --curve-only; done

Prints: IHB unknowns, time per continuation point (wall and CPU) and for the full response
curve (omega 2..12 rad/s) with its corrector updates and sparse factorizations, time per point with Floquet stability, and at a few frequencies the
time to integrate the DAE from rest to steady state next to the IHB time for the same
orbit, their ratio, and the difference between the two orbits after settling.
With 40 rods one period of integration takes ~10 s and the slowest Floquet mode needs
hundreds of periods, so by default the steady-state time is the measured time per period
(over ``--periods``) times the number of periods for the slowest mode (largest |mu| of the
IHB orbit) to shrink the measured deviation to 1e-6; ``--settle`` measures it outright
(use with ``--rods 5``).
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import periodyn  # noqa: E402
from periodyn.arclength import continuation  # noqa: E402
from periodyn.nonlinear import ihb  # noqa: E402
from periodyn.examples.dae_examples import slider_chain_pendulum  # noqa: E402
from periodyn.numerics.integration import integrate
from periodyn.numerics.integration import steady_state  # noqa: E402
from periodyn.nonlinear.ihb_jacobian import FillOrdering  # noqa: E402


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--harmonics", type=int, default=10)
    ap.add_argument("--rods", type=int, default=40)
    ap.add_argument("--omegas", type=float, nargs="+", default=[2.5, 5.0, 11.0])
    ap.add_argument("--max-periods", type=int, default=5000)
    ap.add_argument("--periods", type=int, default=3, help="periods integrated to time one period")
    ap.add_argument("--settle", action="store_true",
                    help="integrate to steady state for real (feasible for small chains, e.g. --rods 5)")
    ap.add_argument("--omega-max", type=float, default=12.0, help="end of the response curve (from 2 rad/s)")
    ap.add_argument("--curve-only", action="store_true", help="time the response curve only (no integration)")
    ap.add_argument("--profile", type=int, default=0, metavar="N",
                    help="profile the response curve and print its N most expensive functions (own time)")
    args = ap.parse_args(argv)
    s = slider_chain_pendulum(args.rods)
    H = args.harmonics
    ihb(s, 5.0, H, stability=None)  # JIT compilation and FFT plans outside the timings
    print(f"periodyn from {os.path.dirname(os.path.dirname(periodyn.__file__))}")
    print(f"slider-chain pendulum: {args.rods + 1} bodies, n = {s.n}, m = {s.m}, H = {H}, "
          f"IHB unknowns = {(s.n + s.m) * (2 * H + 1)}")

    factorizations = [0]  # sparse LU factorizations of the IHB Jacobian during the response curve
    factor = FillOrdering.factor

    def counted(self, J):
        factorizations[0] += 1
        return factor(self, J)
    FillOrdering.factor = counted
    prof = cProfile.Profile() if args.profile else None
    t0, c0 = time.perf_counter(), time.process_time()
    if prof:
        prof.enable()
    br = continuation(s, (2.0, args.omega_max), harmonics=H, stability=None, ds_max=0.1, max_points=600)
    t_curve, c_curve = time.perf_counter() - t0, time.process_time() - c0
    FillOrdering.factor = factor
    if prof:
        prof.disable()
        pstats.Stats(prof).sort_stats("tottime").print_stats(args.profile)
    print(f"response curve 2..{args.omega_max:g} rad/s: {len(br)} points in {t_curve:.2f} s = {t_curve / len(br):.3f} "
          f"s/point (CPU {c_curve / len(br):.3f} s/point) "
          f"(mean {br.iterations.mean():.2f} corrector updates, {factorizations[0]} factorizations, "
          f"max residual {br.residual.max():.2e}); "
          f"folds at {', '.join(f'{p.omega:.4f}' for p in br.points('fold'))} rad/s; status: {br.status}")

    t0 = time.perf_counter()
    for sol in br.solutions[::max(1, len(br) // 8)][:8]:
        ihb(s, sol.omega, H, initial=sol, stability="magnus")
    k = len(br.solutions[::max(1, len(br) // 8)][:8])
    print(f"IHB point + Floquet multipliers (Magnus, {2 * (s.n - s.m)} multipliers): {(time.perf_counter() - t0) / k:.3f} s/point")
    if args.curve_only:
        return dict(points=len(br), s_per_point=t_curve / len(br), curve_s=t_curve)

    print("integration: stabilized index-1 DAE, DOP853 rtol 1e-8, from rest at the hanging chain")
    print(f"{'omega rad/s':>11} {'IHB s':>8} {'int s/period':>12} {'periods':>8} {'int total s':>11} {'ratio':>7} "
          f"{'max|mu|':>8} {'max|dq| IHB-int':>16}")
    ratios = []
    for w in args.omegas:
        j = int(np.argmin(np.abs(br.omega - w)))
        t0 = time.perf_counter()
        sol = ihb(s, w, H, initial=br.solutions[j], stability=None)
        t_ihb = time.perf_counter() - t0
        mu = ihb(s, w, H, initial=sol, stability="magnus").max_multiplier
        T = sol.period
        if args.settle:  # measured: integrate period by period until the state repeats to 1e-6
            t0 = time.perf_counter()
            q, qd, periods, _ = steady_state(s, w, tol=1e-6, max_periods=args.max_periods)
            t_int = time.perf_counter() - t0
            per_period = t_int / periods
            kind = ""
        else:  # measured time per period x periods the slowest Floquet mode needs to decay to 1e-6
            q, qd = s.q0, np.zeros(s.n)
            t0 = time.perf_counter()
            th = integrate(s, w, (0, args.periods * T), q, qd, t_eval=[args.periods * T], rtol=1e-8, atol=1e-10)
            per_period = (time.perf_counter() - t0) / args.periods
            dev = np.abs(th.q[-1] - sol(0.0)[0]).max()
            periods = args.periods + int(np.ceil(np.log(1e-6 / max(dev, 1e-6)) / np.log(mu)))
            t_int = per_period * periods
            q, qd = th.q[-1], th.qd[-1]
            kind = " (estimate)"
        tt = np.linspace(0, T, 17)
        th = integrate(s, w, (0, T), q, qd, t_eval=tt, rtol=1e-8, atol=1e-10)
        err = np.abs(th.q - sol(tt)).max()
        ratios.append(t_int / t_ihb)
        print(f"{w:11.3f} {t_ihb:8.3f} {per_period:12.2f} {periods:8d} {t_int:11.1f} {t_int / t_ihb:7.0f} {mu:8.4f} "
              f"{err:16.2e}{kind}")
    return dict(points=len(br), s_per_point=t_curve / len(br), curve_s=t_curve, ratios=ratios)


if __name__ == "__main__":
    main()
