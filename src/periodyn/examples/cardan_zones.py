"""The Cardan shaft's unstable zones (Schwab & Meijaard 2001, Fig. 9-10): boundaries by
bisection on the largest real part of the Hill exponents, typed by the critical
multiplier, each checked by the monodromy matrix of direct integration.

Run: python -m periodyn.examples.cardan_zones [--harmonics 12] [--samples 64]
"""

from __future__ import annotations

import argparse

import numpy as np

from ..stability.boundaries import BoundaryCheck, check_boundary, stability_boundaries
from ..stability.methods import stability_choice
from .cardan import cardan_shaft

__all__ = ["cardan_boundaries"]

#: speeds (omega / omega_b) bracketing the paper's zones 0.65-0.68 and 0.78-0.92
GRID = np.linspace(0.60, 0.96, 19)


def cardan_boundaries(alpha: float = np.pi / 6, harmonics: int = 12, samples: int = 64, grid=GRID,
                      stability: str = "dense", xtol: float = 1e-8, step: float = 1e-3,
                      truncation: str = "refuse", *, method: str | None = None) -> tuple[float, list[BoundaryCheck]]:
    """(omega_b in rad/s, the boundaries within ``grid`` (omega / omega_b, increasing),
    each with its monodromy check at relative distance ``step``); truncation: "refuse" or
    "warn" for Hill results above the truncation tolerance (the monodromy check still runs);
    stability: the stability method (``method=``, its deprecated spelling, warns)."""
    if method is not None:
        stability = stability_choice(True if stability == "dense" else stability, method, "cardan_boundaries")[1]
    model = cardan_shaft(alpha, samples=samples)
    wb = model.metadata["omega_b"]
    found = stability_boundaries(model.at, np.asarray(grid, float) * wb, harmonics, stability=stability, xtol=xtol,
                                 truncation=truncation)
    return wb, [check_boundary(model.at, b, step) for b in found]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--harmonics", type=int, default=12)
    ap.add_argument("--samples", type=int, default=64)
    args = ap.parse_args(argv)
    wb, checks = cardan_boundaries(harmonics=args.harmonics, samples=args.samples)
    print(f"Cardan shaft, alpha = pi/6, m = {args.harmonics}, {args.samples} samples, omega_b = {wb:.2f} rad/s")
    print(f"{'omega/omega_b':>14}{'omega rad/s':>13}{'type':>16}{'side':>14}"
          f"{'mono Re out':>14}{'mono Re in':>13}{'mono type':>16}{'agrees':>8}")
    for c in checks:
        b = c.boundary
        side = "zone ends" if b.becomes_stable else "zone begins"
        print(f"{b.omega / wb:14.6f}{b.omega:13.4f}{b.kind:>16}{side:>14}{c.max_real_outside:14.3e}"
              f"{c.max_real_inside:13.3e}{c.kind_inside:>16}{str(c.agrees):>8}")


if __name__ == "__main__":
    main()
