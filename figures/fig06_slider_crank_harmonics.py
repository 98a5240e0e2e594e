"""Fig. 6 of Schwab & Meijaard (2001): amplitudes of the first four harmonics of the
slider-crank's midpoint deflection (2 % damping, 150-300 rad/s); dotted: the
quasistatic forcing solution, harmonic k of the forcing times the inverse of the
average stiffness matrix, mapped by the average output map."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import periodyn  # noqa: E402
from periodyn.examples.slider_crank import slider_crank  # noqa: E402

HARMONICS = 12
OMEGA = np.linspace(150.0, 300.0, 601)  # rad/s


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    model = slider_crank(0.02, 64)
    amp = np.empty((OMEGA.size, 4))
    quasi = np.empty((OMEGA.size, 4))
    for i, w in enumerate(OMEGA):
        system = model.at(w)
        periodic = periodyn.periodic_solution(system, HARMONICS)
        m = (periodic.output_harmonics.shape[0] - 1) // 2
        amp[i] = 2 * np.abs(periodic.output_harmonics[m + 1:m + 5, 0])
        spec = system.spectra
        K = (spec.stiffness.shape[0] - 1) // 2
        G0 = spec.outputs[(spec.outputs.shape[0] - 1) // 2].real
        K0 = spec.stiffness[K].real
        quasi[i] = [2 * abs(G0[0] @ np.linalg.solve(K0, spec.force[K + k])) for k in range(1, 5)]
    fig, axes = plt.subplots(4, 1, figsize=(6, 7), sharex=True)
    for k, ax in enumerate(axes, start=1):
        ax.plot(OMEGA, amp[:, k - 1], "k-", lw=1)
        ax.plot(OMEGA, quasi[:, k - 1], "k:", lw=1)
        ax.set_ylim(0, 0.04)
        ax.set_ylabel(f"harmonic {k}")
    axes[-1].set_xlabel(r"$\omega$ [rad/s]")
    axes[0].set_title("slider-crank midpoint deflection harmonics, 2 % damping")
    fig.tight_layout()
    path = out_dir / "fig06_slider_crank_harmonics.png"
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return [path]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
