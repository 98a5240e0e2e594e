"""Campbell diagram of the rotor of Schwab & Meijaard (2001), section 4.3, over
0-8000 rpm: stationary-frame whirl frequencies coloured by whirl direction, marker size
growing as the damping ratio falls, 1x and 2x running-speed lines, the Table I speed
and the stability threshold (if any in range).

Reads (or computes once and stores) results/campbell_rotor.nc made by
periodyn.rotor.diagram."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.studies.spec import project_root  # noqa: E402
from periodyn.examples import rotor  # noqa: E402
from periodyn.plotting import save_figure  # noqa: E402
from periodyn.rotor import FORWARD, stored_campbell  # noqa: E402

RPM = np.linspace(0.0, 8000.0, 401)


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = stored_campbell(project_root() / "results" / "campbell_rotor.nc", rotor(), RPM * np.pi / 30.0, modes=8)
    rpm = ds["speed_rpm"].values
    freq = ds["frequency"].values * 30.0 / np.pi           # rad/s -> rpm-equivalent (cycles per minute)
    zeta = ds["damping_ratio"].values
    forward = ds["whirl"].values == FORWARD
    size = 4.0 + 30.0 * (1.0 - np.clip(zeta / max(zeta.max(), 1e-12), 0.0, 1.0))
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    every = slice(None, None, 4)
    for mask, colour, label in ((forward, "C3", "forward whirl"), (~forward, "C0", "backward whirl")):
        r = np.broadcast_to(rpm[:, None], freq.shape)
        ax.scatter(r[every][mask[every]], freq[every][mask[every]], s=size[every][mask[every]], c=colour,
                   lw=0, label=label)
    for k in (1, 2):
        ax.plot(rpm, k * rpm, "k--" if k == 1 else "k:", lw=0.8, label=f"{k}x running speed")
    ax.axvline(4000.0, color="0.6", lw=0.8)
    ax.text(4000.0, 0.98 * freq.max(), " Table I", fontsize=8, va="top")
    threshold = ds.attrs["threshold_speed"]
    note = (f"stability threshold {threshold * 30 / np.pi:.0f} rpm" if np.isfinite(threshold)
            else "stable over the whole speed range")
    ax.set_title(f"Rotor of section 4.3: {note}; larger markers = less damped", fontsize=9)
    ax.set_xlabel("spin speed [rpm]")
    ax.set_ylabel("whirl frequency [cycles/min]")
    ax.set_xlim(rpm[0], rpm[-1])
    ax.set_ylim(0.0, 1.05 * freq.max())
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    return [save_figure(fig, pathlib.Path(out_dir) / "fig_campbell_rotor.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
