"""Schwab & Meijaard (2001) Fig. 3: log amplitude of the periodic solution of the
elliptic pendulum and the largest real part of the characteristic exponents (lambda/omega0),
zeta = 0.01, 0 < omega/omega0 < 1.4, with the stability boundaries the sweep refined
(``boundaries = true`` in sweeps/pendulum.toml)."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.plotting import figure_result, save_figure  # noqa: E402


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = figure_result("pendulum")
    w0 = float(ds["omega_over_omega0"].attrs["reference_frequency"])
    r = ds["omega_over_omega0"].values
    amp = ds["amplitude"].sel(output="phi").values
    max_real = ds["max_real_exponent"].values / w0
    stable = ds["stable"].values.astype(bool)

    fig, ax = plt.subplots(figsize=(6.5, 4.6), layout="constrained")
    ax.semilogy(r, np.where(stable, amp, np.nan), "k-", lw=1.2, label=r"$\Delta\hat\varphi$ (stable)")
    ax.semilogy(r, np.where(stable, np.nan, amp), color="0.6", lw=0.8, label=r"$\Delta\hat\varphi$ (unstable)")
    ax.set_xlabel(r"$\omega/\omega_0$")
    ax.set_ylabel(r"$\Delta\hat\varphi$ [rad]")
    ax.set_xlim(0, 1.4)
    ax2 = ax.twinx()
    ax2.plot(r, max_real, "b--", lw=1.0, label=r"max Re $\lambda/\omega_0$")
    ax2.axhline(0.0, color="b", lw=0.4)
    ax2.set_ylabel(r"max Re $\lambda/\omega_0$", color="b")
    for omega, kind in zip(ds["boundary_omega"].values / w0, ds["boundary_kind"].values):
        ax.axvline(omega, color="r", lw=0.5, ls=":")
        ax.text(omega, ax.get_ylim()[1], f"{omega:.4f}\n{kind}", fontsize=6, ha="center", va="bottom", color="r")
    lines = ax.get_legend_handles_labels()[0] + ax2.get_legend_handles_labels()[0]
    fig.legend(lines, [ln.get_label() for ln in lines], loc="outside lower center", ncols=3, fontsize=8)
    return [save_figure(fig, out_dir / "fig03_pendulum_stability.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
