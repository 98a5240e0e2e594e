"""Rod pendulum (Ju, Fan & Zhu 2021, eqs. 61-62): amplitude-frequency curve with folds,
amplitude-forcing curve, and q, lambda over one period: EGA-IHB vs integration.

    python figures/fig_dae_rod_pendulum.py [OUT_DIR]
"""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.nonlinear import ihb  # noqa: E402
from periodyn.plotting import (drawn_branch, figure_result, figure_study, plot_branch, save_figure,  # noqa: E402
                               time_history_figure)
from periodyn.numerics.integration import integrate
from periodyn.numerics.integration import steady_state  # noqa: E402


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    out_dir = pathlib.Path(out_dir)
    spec = figure_study("dae_rod_pendulum")
    branches = figure_result("dae_rod_pendulum")  # computed when missing
    s = spec.build()
    H = spec.harmonics
    br = drawn_branch(branches["frequency"])
    pc = spec.parameter
    brp = drawn_branch(branches["parameter"])
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    plot_branch(axes[0], br, 2)
    axes[0].set_xlabel("omega (rad/s)")
    axes[0].set_ylabel("phi amplitude (rad)")
    axes[0].set_title(f"frequency response, f = {s.parameters['f']} N m, H = {H}", fontsize=9)
    plot_branch(axes[1], brp, 2)
    axes[1].set_xlabel("f (N m)")
    axes[1].set_title(f"forcing amplitude at omega = {pc['omega']} rad/s", fontsize=9)
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    p1 = save_figure(fig, out_dir / "fig_dae_rod_pendulum_response.png")

    w = spec.time_history_omega
    q, qd, _, _ = steady_state(s, w, tol=1e-8, max_periods=3000)
    T = 2 * np.pi / w
    th = integrate(s, w, (0, T), q, qd, t_eval=np.linspace(0, T, 40))
    sol = ihb(s, w, H, initial=q)
    fig = time_history_figure(sol, th, [0, 1, 2], [0, 1], ["x", "y", "phi"], ["lambda_x", "lambda_y"],
                              f"rod pendulum, omega = {w} rad/s: IHB (H = {H}, residual {sol.residual:.1e}) vs integration")
    p2 = save_figure(fig, out_dir / "fig_dae_rod_pendulum_time.png")
    return [p1, p2]


if __name__ == "__main__":
    print(main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "figures/png")))
