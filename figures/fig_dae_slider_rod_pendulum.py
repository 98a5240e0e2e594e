"""Slider-rod pendulum (Ju, Fan & Zhu 2021, eqs. 65-69): amplitude-frequency curves of the
slider and the rod, and q, lambda over one period vs integration.

    python figures/fig_dae_slider_rod_pendulum.py [OUT_DIR]
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
    spec = figure_study("dae_slider_rod_pendulum")
    branches = figure_result("dae_slider_rod_pendulum")  # computed when missing
    H = spec.harmonics
    br = drawn_branch(branches["frequency"])
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    plot_branch(axes[0], br, 0)
    axes[0].set_ylabel("slider x1 amplitude (m)")
    plot_branch(axes[1], br, 4)
    axes[1].set_ylabel("rod phi2 amplitude (rad)")
    for ax in axes:
        ax.set_xlabel("omega (rad/s)")
        ax.grid(alpha=0.3)
    fig.suptitle(f"slider-rod pendulum, f = {spec.parameters['f']} N, H = {H}", fontsize=9)
    fig.tight_layout()
    p1 = save_figure(fig, out_dir / "fig_dae_slider_rod_pendulum_response.png")

    th = figure_group("dae_slider_rod_pendulum", "time_history")
    fig = time_history_figure(th, ["x_slider", "phi_rod"], ["lambda_s0", "lambda_j0_x", "lambda_j0_y"],
                              ["x1", "phi2"], ["lambda_slider", "lambda_jx", "lambda_jy"],
                              f"slider-rod pendulum, omega = {th.attrs['omega']:.3f} rad/s: IHB vs integration")
    p2 = save_figure(fig, out_dir / "fig_dae_slider_rod_pendulum_time.png")
    return [p1, p2]


if __name__ == "__main__":
    print(main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "figures/png")))
