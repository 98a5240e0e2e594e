"""Fig. 4 of Schwab & Meijaard (2001): dimensionless midpoint deflection of the
slider-crank's connecting rod at omega = 150 rad/s, 2 % damping: periodic solution, and
periodic + transient from rest (averaging, eq. 24, and direct integration) over the
first period."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import periodyn  # noqa: E402
from periodyn.examples.slider_crank import slider_crank  # noqa: E402

OMEGA = 150.0  # rad/s
HARMONICS = 12


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    system = slider_crank(0.02, 64).at(OMEGA)
    periodic = periodyn.periodic_solution(system, HARMONICS)
    t = np.linspace(0.0, 2 * np.pi / OMEGA, 401)
    y0 = np.zeros(2 * system.n)
    averaged = periodyn.transient(system, periodic, y0, t, method="averaging")
    direct = periodyn.transient(system, periodic, y0, t, method="integrate")
    fig, ax = plt.subplots(figsize=(6, 3.5))
    theta = OMEGA * t
    ax.plot(theta, averaged.periodic_outputs[:, 0], "k-", lw=1.5, label="periodic (HB)")
    ax.plot(theta, averaged.outputs[:, 0], "C0-", lw=1, label="periodic + transient (averaging)")
    ax.plot(theta, direct.outputs[:, 0], "C1--", lw=1, label="periodic + transient (integration)")
    ax.set_xlabel(r"crank angle $\omega t$ [rad]")
    ax.set_ylabel("midpoint deflection / rod length [-]")
    ax.set_title(r"slider-crank, $\omega$ = 150 rad/s, 2 % damping")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = out_dir / "fig04_slider_crank_transient.png"
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return [path]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
