"""Fig. 10 of Schwab & Meijaard (2001): maximal twist angle of the Cardan drive shaft's
periodic solution over 0 < omega/omega_b < 1, unstable stretches thin between circles;
the static twist at zero misalignment, M_o L / (G J), is drawn dashed.

Reads the results of ``sweeps/cardan_shaft.toml`` (computed and stored on first use);
squares: the full non-linear orbits of ``sweeps/cardan_shaft_nonlinear.toml`` (as in Fig. 9)."""

from __future__ import annotations

import pathlib
import sys

from periodyn.plotting import figure_result, save_figure  # noqa: E402

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from fig09_cardan_max_deflection import (NAME, draw_nonlinear, maximum_figure, nonlinear_points,  # noqa: E402
                                         over_period)

STATIC_TWIST = 1060.288 * 1.0 / (210e9 / 2.6 * 3.141592653589793 * 0.03**4 / 2)   # rad


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = figure_result(NAME)
    fig, ax = maximum_figure(ds, over_period(ds, "twist").max(axis=1), r"$\varphi_{max}$ [rad]",
                             r"Cardan shaft, $\alpha = \pi/6$: twist (dashed: static, $\alpha = 0$)")
    ax.axhline(STATIC_TWIST, color="0.5", ls="--", lw=0.8)
    draw_nonlinear(ax, nonlinear_points(), "twist", legend="upper right")
    fig.tight_layout()
    return [save_figure(fig, pathlib.Path(out_dir) / "fig10_cardan_max_twist.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
