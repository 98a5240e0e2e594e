"""Fig. 11 of Schwab & Meijaard (2001): amplitudes (log scale) of harmonics 0-6 of the
Cardan drive shaft's dimensionless midpoint deflection over 0 < omega/omega_b < 1; the
even harmonics vanish by the symmetry of the system (drawn at round-off level).

Reads the results of ``sweeps/cardan_shaft.toml`` (computed and stored on first use)."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.plotting import figure_result, save_figure  # noqa: E402

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from fig09_cardan_max_deflection import NAME, speed_ratio  # noqa: E402

ORDERS = range(7)


def harmonic_panels(ds, output: str, label: str, path: pathlib.Path) -> pathlib.Path:
    """One panel per harmonic k: amplitude (2 |c_k| for k > 0, |c_0| for the mean)."""
    harmonics = ds["harmonics"].sel(output=output).values      # (k, 2m+1), l = -m..m
    m = (harmonics.shape[1] - 1) // 2
    ratio = speed_ratio(ds)
    floor = 1e-16 * np.abs(harmonics).max()
    fig, axes = plt.subplots(len(ORDERS), 1, figsize=(6, 9), sharex=True)
    for k, ax in zip(ORDERS, axes):
        amp = np.abs(harmonics[:, m + k]) * (1 if k == 0 else 2)
        ax.semilogy(ratio, np.maximum(amp, floor), "k-", lw=0.8)
        ax.set_ylabel(f"{k}", rotation=0, labelpad=10)
    axes[0].set_title(f"Cardan shaft: harmonics of {label}", fontsize=9)
    axes[-1].set_xlabel(r"$\omega/\omega_b$ [-]")
    axes[-1].set_xlim(0, 1)
    fig.tight_layout()
    return save_figure(fig, path)


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = figure_result(NAME)
    return [harmonic_panels(ds, "midpoint_deflection", "the midpoint deflection v/l",
                            pathlib.Path(out_dir) / "fig11_cardan_deflection_harmonics.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
