"""Schwab & Meijaard (2001) Fig. 2: amplitude of the periodic solution of the elliptic
pendulum, zeta = 0.01, 0 < omega/omega0 < 0.9: linearized eq. (29) from
sweeps/pendulum.toml (black) and the full non-linear eq. (28) by shooting with arc-length
continuation from sweeps/pendulum_nonlinear.toml (red: solid where the orbit is stable,
dashed where unstable by the multipliers of the shooting monodromy; folds and period
doublings marked). The non-linear resonance near 0.9 omega0 bends backwards through a fold
(0.88 omega0) and turns again (0.50 omega0) onto a large-amplitude upper branch, unstable
between its period doublings (0.51 and 0.83 omega0) and stable above."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.plotting import figure_result, plot_branch, save_figure, unique_legend  # noqa: E402


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = figure_result("pendulum")
    r = ds["omega_over_omega0"].values
    amp = ds["amplitude"].sel(output="phi").values
    keep = r <= 0.9
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(r[keep], amp[keep], "k-", lw=1.2, label="linearized, eq. (29)")
    w0 = float(ds["omega_over_omega0"].attrs["reference_frequency"])
    branch = figure_result("pendulum_nonlinear")["frequency"]
    plot_branch(ax, branch, 0, "non-linear, eq. (28),", color="C3", x=np.asarray(branch.omega) / w0)
    ax.set_xlabel(r"$\omega/\omega_0$")
    ax.set_ylabel(r"$\Delta\hat\varphi$ [rad]")
    ax.set_xlim(0, 0.9)
    ax.set_ylim(0, None)
    ax.set_title(r"Elliptic pendulum, $\zeta = 0.01$ (Fig. 2)")
    unique_legend(ax, loc="upper left", fontsize=7)
    fig.tight_layout()
    return [save_figure(fig, out_dir / "fig02_pendulum_amplitude.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
