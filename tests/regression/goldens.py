"""Golden regression values: small, exactly reproducible results whose change must be
reviewed. Regenerate after an intended change with

    python -m tests.regression.goldens

and review the diff of tests/regression/golden/*.json before committing.
"""

from __future__ import annotations

import json
import pathlib

import numpy as np

import periodyn
from periodyn.speeds import SpeedSolver

GOLDEN = pathlib.Path(__file__).parent / "golden"


def pendulum_sweep(method: str = "dense") -> dict:
    """Linearized pendulum (eq. 29): amplitude, mean, max Re exponent at 15 speeds, m = 12,
    stability by dense Hill (or ``method``)."""
    model = periodyn.examples.pendulum(samples=64)
    r = np.linspace(0.1, 1.4, 15)
    solver = SpeedSolver(model, 12, method=method)
    points = [solver.solve(x * model.metadata["omega0"]) for x in r]
    out = {"omega_over_omega0": r.tolist(), "amplitude": [float(p.amplitude[0]) for p in points],
           "mean": [float(p.mean[0]) for p in points], "max_real": [p.max_real for p in points]}
    if method == "auto":
        out["method"] = [p.method for p in points]
    return out


def pendulum_sweep_auto() -> dict:
    """:func:`pendulum_sweep` with the default stability method, and what it chose."""
    return pendulum_sweep("auto")


CASES = {"pendulum_sweep": pendulum_sweep, "pendulum_sweep_auto": pendulum_sweep_auto}


def main() -> None:
    GOLDEN.mkdir(exist_ok=True)
    for name, fun in CASES.items():
        (GOLDEN / f"{name}.json").write_text(json.dumps(fun(), indent=1) + "\n")
        print(f"wrote {GOLDEN / name}.json")


if __name__ == "__main__":
    main()
