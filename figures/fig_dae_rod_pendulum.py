"""Rod pendulum (Ju, Fan & Zhu 2021, eqs. 61-62): amplitude-frequency curve with folds,
amplitude-forcing curve, and q, lambda over one period: EGA-IHB vs integration (the
study's time history: the orbit the motion from rest settles to, integrated over one period
from that state, against EGA-IHB started there).

    python figures/fig_dae_rod_pendulum.py [OUT_DIR]
"""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from periodyn.plotting import (drawn_branch, figure_group, figure_result, figure_study, plot_branch,  # noqa: E402
                               save_figure, time_history_figure)


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    out_dir = pathlib.Path(out_dir)
    spec = figure_study("dae_rod_pendulum")
    branches = figure_result("dae_rod_pendulum")  # computed when missing
    H = spec.harmonics
    br = drawn_branch(branches["frequency"])
    pc = spec.parameter
    brp = drawn_branch(branches["parameter"])
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    plot_branch(axes[0], br, 2)
    axes[0].set_xlabel("omega (rad/s)")
    axes[0].set_ylabel("phi amplitude (rad)")
    axes[0].set_title(f"frequency response, f = {spec.parameters['f']} N m, H = {H}", fontsize=9)
    plot_branch(axes[1], brp, 2)
    axes[1].set_xlabel("f (N m)")
    axes[1].set_title(f"forcing amplitude at omega = {pc['omega']} rad/s", fontsize=9)
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    p1 = save_figure(fig, out_dir / "fig_dae_rod_pendulum_response.png")

    th = figure_group("dae_rod_pendulum", "time_history")
    fig = time_history_figure(th, ["x_rod", "y_rod", "phi_rod"], ["lambda_j0_x", "lambda_j0_y"], ["x", "y", "phi"],
                              ["lambda_x", "lambda_y"],
                              f"rod pendulum, omega = {th.attrs['omega']:g} rad/s: IHB (H = {H}, residual "
                              f"{th.attrs['orbit_residual']:.1e}) vs integration")
    p2 = save_figure(fig, out_dir / "fig_dae_rod_pendulum_time.png")
    return [p1, p2]


if __name__ == "__main__":
    print(main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "figures/png")))
