"""Fig. 6 of Schwab & Meijaard (2001): amplitudes of the first four harmonics of the
slider-crank's midpoint deflection (2 % damping, 150-300 rad/s); dotted: the
quasistatic forcing solution, harmonic k of the forcing times the inverse of the
average stiffness matrix, mapped by the average output map.

Reads the results of ``sweeps/slider_crank.toml`` (computed and stored on first use), the
quasistatic reference too (``quasistatic = 4``: from the model's mean coefficients at the
same speeds)."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.plotting import figure_result, save_figure  # noqa: E402

DAMPING = 0.02


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = figure_result("slider_crank").sel(damping=DAMPING, output="midpoint_deflection")
    omega = ds["omega"].values
    harmonics = ds["harmonics"].values  # (k, 2m+1), l = -m..m
    m = (harmonics.shape[1] - 1) // 2
    quasi = ds["quasistatic_amplitude"].sel(quasistatic_harmonic=[1, 2, 3, 4]).values  # (k, 4)
    fig, axes = plt.subplots(4, 1, figsize=(6, 7), sharex=True)
    for k, ax in enumerate(axes, start=1):
        ax.plot(omega, 2 * np.abs(harmonics[:, m + k]), "k-", lw=1)
        ax.plot(omega, quasi[:, k - 1], "k:", lw=1)
        ax.set_ylim(0, 0.04)
        ax.set_ylabel(f"harmonic {k}")
    axes[-1].set_xlabel(r"$\omega$ [rad/s]")
    axes[0].set_title(f"slider-crank midpoint deflection harmonics, {DAMPING:.0%} damping")
    fig.tight_layout()
    return [save_figure(fig, pathlib.Path(out_dir) / "fig06_slider_crank_harmonics.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
