"""Every Neimark-Sacker point of the 41-body slider-chain study checked by direct integration.

    OPENBLAS_NUM_THREADS=1 python benchmarks/confirm_chain.py results/dae_slider_chain_pendulum.nc
        [--rtol 1e-8] [--types neimark-sacker ...]

Reads the study file written by ``periodyn sweep sweeps/dae_slider_chain_pendulum.toml``
(computes it when absent), runs ``confirm_special_points`` on its frequency branch (one
period of the DAE with its variational equations per bracketing orbit, ~100-200 s each for
82 multipliers) and prints each point's verdict and reason, and the time spent.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from periodyn.config import load_sweep_file  # noqa: E402
from periodyn.continuation import confirm_special_points  # noqa: E402
from periodyn.study import ensure_study  # noqa: E402

STUDY = os.path.join(os.path.dirname(__file__), "..", "sweeps", "dae_slider_chain_pendulum.toml")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("result", help="study result file (computed there when absent)")
    ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--types", nargs="+", default=["neimark-sacker"])
    args = ap.parse_args(argv)
    spec = load_sweep_file(STUDY)
    branch = ensure_study(spec, args.result)["frequency"]
    start = time.perf_counter()
    checked = confirm_special_points(branch, spec.build(), rtol=args.rtol, types=tuple(args.types),
                                     progress=lambda k, n: print(f"checked {k}/{n}", file=sys.stderr, flush=True))
    for sp in checked.special_points:
        if sp.type in args.types:
            print(f"{sp.type:15s} omega {sp.omega:.5f} (bracket {branch.omega[sp.index]:.5f}-"
                  f"{branch.omega[sp.index + 1]:.5f}) refined {sp.solution is not None}: {sp.check}", flush=True)
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
