"""Cost of continuation's defaults on the rod pendulum (m = l = 1, eps = 0.1, f = 1, g = 9.81):
wall seconds of ``continuation(rod, omega)`` with the defaults (harmonics grown until the
orbit defect is resolved, truncation check of every special point) against the former ones
(harmonics=5, confirm=False), for omega = (1, 8) and (8, 1), side by side in one run (best of
--rounds, one BLAS/Numba thread). The former defaults on (8, 1) are timed on the same call
with the range check and landing of this tree (on older trees that call stepped to omega < 0).

Run: python benchmarks/bench_continuation_defaults.py [--rounds 1]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

from periodyn.arclength import continuation  # noqa: E402
from periodyn.examples import rod_pendulum  # noqa: E402


def best(call, rounds):
    """(best wall seconds of rounds, the result of the last call)."""
    t, out = float("inf"), None
    for _ in range(rounds):
        t0 = time.perf_counter()
        out = call()
        t = min(t, time.perf_counter() - t0)
    return t, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=1)
    args = ap.parse_args()
    rod = rod_pendulum(m1=1, l=1, eps1=0.1, f=1, g=9.81)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        continuation(rod, (3.0, 3.2), harmonics=5, confirm=False)  # compile and warm the kernels
    print(f"{'omega':>8} {'former s':>9} {'points':>6} {'specials':>8} {'defaults s':>10} {'H':>3} {'points':>6} "
          f"{'specials':>8} {'flagged':>7} {'ratio':>6}")
    for omega in ((1.0, 8.0), (8.0, 1.0)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t_old, old = best(lambda: continuation(rod, omega, harmonics=5, confirm=False), args.rounds)
            t_new, new = best(lambda: continuation(rod, omega), args.rounds)
        flagged = sum(p.confirmed is False for p in new.special_points)
        print(f"{str(omega):>8} {t_old:9.2f} {len(old):6d} {len(old.special_points):8d} {t_new:10.2f} "
              f"{new.options['harmonics']:3d} {len(new):6d} {len(new.special_points):8d} {flagged:7d} "
              f"{t_new / t_old:6.2f}")


if __name__ == "__main__":
    main()
