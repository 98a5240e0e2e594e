"""Two-parameter stability charts: the Cardan shaft's unstable zones over the misalignment
alpha (the zones of Fig. 9-10 at alpha = pi/6 marked) and the elliptic pendulum's over the
damping zeta; each boundary followed by continuation of the crossing condition, its type
(fold, period doubling, Neimark-Sacker) by colour, the tips where a zone closes, and the
monodromy checks.

Reads the results of sweeps/cardan_chart.toml and sweeps/pendulum_chart.toml (computed by
``periodyn sweep`` when missing, through ``periodyn.plotting.figure_result``)."""

from __future__ import annotations

import math
import pathlib
import sys

from periodyn.plotting import figure_result, plot_stability_chart, save_figure  # noqa: E402


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    out = []
    cardan = plot_stability_chart(figure_result("cardan_chart"), "Cardan shaft (sec. 4.4), 1 % damping")
    ax = cardan.axes[0]
    ax.axhline(math.pi / 6, color="0.5", lw=0.8, ls="--")
    ax.text(ax.get_xlim()[0], math.pi / 6, " α = π/6 (Fig. 9-10)", fontsize=7, va="bottom")
    out.append(save_figure(cardan, pathlib.Path(out_dir) / "fig_chart_cardan_alpha.png"))
    pendulum = plot_stability_chart(figure_result("pendulum_chart"), "Elliptic pendulum, eq. (29)")
    out.append(save_figure(pendulum, pathlib.Path(out_dir) / "fig_chart_pendulum_zeta.png"))
    return out


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
