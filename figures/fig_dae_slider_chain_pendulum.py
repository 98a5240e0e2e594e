"""Slider-chain pendulum with 40 rods (Ju, Fan & Zhu 2021, eqs. 70-82; n = 122, m = 81):
amplitude-frequency curves of the slider and the chain tip, and q, lambda over one period
vs integration of the DAE started on the IHB orbit.

Special points: only those the study's check did not reject are drawn (the study runs
``confirm = "truncation"``: a point whose H = 10 orbit is unresolved and whose crossing is not
found on a resolved H = 14 orbit within 1 % is spurious); the title says how many were left out.

    python figures/fig_dae_slider_chain_pendulum.py [OUT_DIR]
"""

from __future__ import annotations

import pathlib
import sys
from dataclasses import replace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from periodyn.plotting import (drawn_branch, figure_group, figure_result, figure_study, plot_branch,  # noqa: E402
                               save_figure, time_history_figure)


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    out_dir = pathlib.Path(out_dir)
    spec = figure_study("dae_slider_chain_pendulum")
    branches = figure_result("dae_slider_chain_pendulum")  # computed when missing
    H = spec.harmonics
    br = branches["frequency"]
    coordinates, constraints = br.solutions[0].coordinate_names, br.solutions[0].constraint_names
    kept = tuple(p for p in br.special_points if p.confirmed is not False)
    drawn = drawn_branch(replace(br, special_points=kept))
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    plot_branch(axes[0], drawn, 0)
    axes[0].set_ylabel("slider x1 amplitude (m)")
    plot_branch(axes[1], drawn, coordinates.index("x_rod41"))
    axes[1].set_ylabel("last rod x41 amplitude (m)")
    for ax in axes:
        ax.set_xlabel("omega (rad/s)")
        ax.grid(alpha=0.3)
    fig.suptitle(f"slider-chain pendulum, {len(coordinates)} coordinates, {len(constraints)} multipliers, "
                 f"p = {spec.parameters['p']} N, "
                 f"H = {H}, max residual {br.residual.max():.1e}\n"
                 f"special points drawn: {len(drawn.special_points)} not rejected (each once); "
                 f"{len(br.special_points) - len(kept)} spurious left out (orbit unresolved, no resolved crossing "
                 f"at H = {H + 4})",
                 fontsize=9)
    fig.tight_layout()
    p1 = save_figure(fig, out_dir / "fig_dae_slider_chain_pendulum_response.png")

    th = figure_group("dae_slider_chain_pendulum", "time_history")
    fig = time_history_figure(th, ["x_slider", "x_rod41"], ["lambda_s0", "lambda_j0_x", constraints[-1]],
                              ["x1", "x41"], ["lambda slider", "lambda joint 1 x", "lambda last joint y"],
                              f"slider-chain pendulum, omega = {th.attrs['omega']:.3f} rad/s: IHB vs integration over "
                              "one period")
    p2 = save_figure(fig, out_dir / "fig_dae_slider_chain_pendulum_time.png")
    return [p1, p2]


if __name__ == "__main__":
    print(main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "figures/png")))
