"""Campbell diagram of the rotor of Schwab & Meijaard (2001), section 4.3, over
0-8000 rpm: stationary-frame whirl frequencies coloured by whirl direction, marker size
growing as the damping ratio falls, 1x and 2x running-speed lines, the Table I speed
and the stability threshold (if any in range).

Reads the result of sweeps/rotor_campbell.toml (computed by ``periodyn sweep`` when
missing, through ``periodyn.plotting.figure_result``)."""

from __future__ import annotations

import pathlib
import sys

from periodyn.plotting import figure_result, plot_campbell, save_figure  # noqa: E402


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = figure_result("rotor_campbell")
    fig = plot_campbell(ds, "Rotor of section 4.3")
    ax = fig.axes[0]
    ax.axvline(4000.0, color="0.6", lw=0.8)
    ax.text(4000.0, 0.98 * ax.get_ylim()[1], " Table I", fontsize=8, va="top")
    return [save_figure(fig, pathlib.Path(out_dir) / "fig_campbell_rotor.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
