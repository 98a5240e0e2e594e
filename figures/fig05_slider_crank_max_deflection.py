"""Fig. 5 of Schwab & Meijaard (2001): maximal dimensionless midpoint deflection of the
slider-crank's periodic solution for 1 % and 2 % damping, 150-300 rad/s; resonances
near 1/5, 1/4 and 1/3 of the first bending frequency (832 rad/s) are marked."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.sweep import sweep  # noqa: E402
from periodyn.examples.slider_crank import first_bending_frequency, slider_crank, slider_crank_model  # noqa: E402

HARMONICS = 12
OMEGA = np.linspace(150.0, 300.0, 601)  # rad/s


def max_deflection(model, omega: np.ndarray) -> np.ndarray:
    """max |y| over one period of the periodic midpoint deflection at each speed, (k,),
    from the harmonics of a periodyn sweep (no stability needed here)."""
    ds = sweep(model, omega, HARMONICS, stability=False, progress=False)
    coefficients = ds["harmonics"].sel(output="midpoint_deflection").values  # (k, 2m+1)
    theta = np.linspace(0.0, 2 * np.pi, 512, endpoint=False)
    basis = np.exp(1j * np.outer(ds["harmonic"].values, theta))  # (2m+1, 512)
    return np.abs((coefficients @ basis).real).max(axis=1)


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    w1 = first_bending_frequency(slider_crank_model())
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for damping, style in ((0.01, "C0-"), (0.02, "k-")):
        ax.plot(OMEGA, max_deflection(slider_crank(damping, 64), OMEGA), style, lw=1,
                label=f"{damping:.0%} damping")
    for k in (5, 4, 3):
        ax.axvline(w1 / k, color="0.6", ls=":", lw=0.8)
        ax.text(w1 / k, ax.get_ylim()[1] * 0.95, f"$\\omega_1/{k}$", ha="center", va="top", fontsize=8)
    ax.set_xlabel(r"$\omega$ [rad/s]")
    ax.set_ylabel("max midpoint deflection / rod length [-]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = out_dir / "fig05_slider_crank_max_deflection.png"
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return [path]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
