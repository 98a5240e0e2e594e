"""Inverted pendulum on a moving base (Ju, Fan & Zhu 2021, eqs. 63-64): period-1 branch with
its period-doubling points, the period-doubled (2T) branch, an amplitude-base-amplitude
curve, and the 2T orbit (q, lambda) vs integration. Solid stable, dashed unstable. The 2T
branch is drawn from the period doubling it is born at to the one where it rejoins the
period-1 branch (beyond, the continuation retraces it as the orbits shifted by T), each
special point once (``periodyn.plotting.drawn_branch``).

    python figures/fig_dae_inverted_pendulum.py [OUT_DIR]
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
    spec = figure_study("dae_inverted_pendulum")
    branches = figure_result("dae_inverted_pendulum")  # computed when missing
    H = spec.harmonics
    br = drawn_branch(branches["frequency"])
    b2 = drawn_branch(branches["period_doubled"], parent=br)
    pc = spec.parameter
    brp = drawn_branch(branches["parameter"])
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    plot_branch(axes[0], br, 2, "period 1")
    plot_branch(axes[0], b2, 2, "period 2", color="tab:orange")
    axes[0].set_xlim(min(spec.omega[0], b2.omega.min()), max(spec.omega[1], b2.omega.max()))
    axes[0].set_xlabel("omega (rad/s)")
    axes[0].set_ylabel("phi amplitude (rad)")
    axes[0].set_title(f"base amplitude p = {spec.parameters['p']} m, H = {H} (2H on the 2T branch)", fontsize=9)
    plot_branch(axes[1], brp, 2, "period 1")
    axes[1].set_xlabel("p (m)")
    axes[1].set_title(f"base amplitude at omega = {pc['omega']} rad/s", fontsize=9)
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    p1 = save_figure(fig, out_dir / "fig_dae_inverted_pendulum_response.png")

    th = figure_group("dae_inverted_pendulum", "time_history")
    fig = time_history_figure(th, ["phi_rod"], ["lambda_j0_x", "lambda_j0_y"], ["phi"], ["lambda_x", "lambda_y"],
                              f"period-doubled orbit at omega = {th.attrs['omega']:.3f} rad/s: IHB vs integration "
                              "(shooting start)")
    p2 = save_figure(fig, out_dir / "fig_dae_inverted_pendulum_time.png")
    return [p1, p2]


if __name__ == "__main__":
    print(main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "figures/png")))
