"""Calibration of Hill's truncation tolerance (periodyn.stability.floquet.TRUNCATION_TOL).

Random elliptic pendulums (l 0.3-3 m, r/l 0.05-2.5, zeta 0 / 0.01 / 0.05, 64 samples) at
4 speeds each in 0.3-3 omega0: dense Hill with m = 1, 2, 3, 4, 6 against the DOP853 monodromy.
For each edge tolerance it prints how many results it flags, how many wrong verdicts it
leaves unflagged and the largest error of log max|mu| among the unflagged ones.

Run: PYTHONPATH=src python benchmarks/truncation_tolerance.py   (a few minutes)
"""

from __future__ import annotations

import warnings

import numpy as np

import periodyn
from periodyn.examples import pendulum


def main(cases: int = 60, seed: int = 1) -> None:
    warnings.simplefilter("ignore", periodyn.TruncationWarning)
    rng = np.random.default_rng(seed)
    rows = []
    for _ in range(cases):
        length = rng.uniform(0.3, 3.0)
        model = pendulum(length=length, radius=rng.uniform(0.05, 2.5) * length, zeta=rng.choice([0.0, 0.01, 0.05]),
                         samples=64)
        for w in np.sqrt(9.81 / length) * rng.uniform(0.3, 3.0, 4):
            ref = periodyn.characteristic_exponents(model.at(w), 1, method="monodromy")
            for m in (1, 2, 3, 4, 6):
                try:
                    hill = periodyn.characteristic_exponents(model.at(w), m, method="dense", truncation="warn")
                except periodyn.ConvergenceError:
                    continue
                rows.append((hill.stable != ref.stable, abs(np.log(hill.max_multiplier) - np.log(ref.max_multiplier)),
                             hill.truncation))
    wrong, error, edge = (np.array(c) for c in zip(*rows))
    print(f"{len(rows)} Hill results, {int(wrong.sum())} wrong verdicts")
    print(f"{'tolerance':>10}{'flagged':>9}{'wrong unflagged':>17}{'max log error unflagged':>26}")
    for tol in (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-8):
        kept = ~(edge > tol)
        print(f"{tol:10.0e}{int((~kept).sum()):9d}{int((wrong & kept).sum()):17d}{error[kept].max():26.2e}")


if __name__ == "__main__":
    main()
