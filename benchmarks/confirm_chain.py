"""Every special point of the 41-body slider-chain study checked: truncation first, then integration.

    OPENBLAS_NUM_THREADS=1 python benchmarks/confirm_chain.py results/dae_slider_chain_pendulum.nc
        [--types neimark-sacker ...] [--harmonics 14] [--integrate] [--rtol 1e-8]

Reads the study file written by ``periodyn sweep sweeps/dae_slider_chain_pendulum.toml``
(computes it when absent; the study already runs step 1, timed again here). Step 1
(``check_truncation``): the orbit defect of every point and, where it is above 1e-3, the
branch continued afresh at H' harmonics around it; points whose crossing is not found on a
resolved H' orbit are spurious. Step 2 (``--integrate``, ``confirm_special_points``): the
survivors by one period of the DAE with its variational equations per bracketing orbit
(40-120 s each for 82 multipliers under load). Prints one line per point (omega, defect,
verdict, reason) and the time of each step.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from periodyn.studies.spec import ensure_result, load_sweep_file  # noqa: E402
from periodyn.arclength import confirm_special_points  # noqa: E402
from periodyn.arclength.truncation import check_truncation  # noqa: E402

STUDY = os.path.join(os.path.dirname(__file__), "..", "sweeps", "dae_slider_chain_pendulum.toml")


def _table(branch, types, title):
    print(f"-- {title}")
    print(f"{'type':15s} {'omega':>9s} {'bracket':>17s} {'defect':>8s}  verdict: reason")
    for sp in branch.special_points:
        if sp.type in types:
            verdict = {None: "open", True: "confirmed", False: "rejected"}[sp.confirmed]
            print(f"{sp.type:15s} {sp.omega:9.5f} {branch.omega[sp.index]:8.5f}-{branch.omega[sp.index + 1]:8.5f} "
                  f"{sp.defect:8.2g}  {verdict}: {sp.check}", flush=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("result", help="study result file (computed there when absent)")
    ap.add_argument("--types", nargs="+", default=["neimark-sacker"])
    ap.add_argument("--harmonics", type=int, default=None, help="H' of the re-solve (default H + 4)")
    ap.add_argument("--integrate", action="store_true", help="step 2: integrate the points step 1 leaves open")
    ap.add_argument("--rtol", type=float, default=1e-8)
    args = ap.parse_args(argv)
    spec = load_sweep_file(STUDY)
    branch = ensure_result(spec, args.result, progress=sys.stderr)["frequency"]
    system, types = spec.build(), tuple(args.types)
    report = lambda k, n: print(f"checked {k}/{n}", file=sys.stderr, flush=True)  # noqa: E731
    start = time.perf_counter()
    checked = check_truncation(branch, system, harmonics=args.harmonics, types=types, progress=report)
    _table(checked, types, f"step 1, truncation: {time.perf_counter() - start:.0f} s")
    if args.integrate:
        start = time.perf_counter()
        checked = confirm_special_points(checked, system, rtol=args.rtol, types=types, progress=report)
        _table(checked, types, f"step 2, integration of the open points: {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
