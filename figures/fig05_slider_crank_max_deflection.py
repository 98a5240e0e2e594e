"""Fig. 5 of Schwab & Meijaard (2001): maximal dimensionless midpoint deflection of the
slider-crank's periodic solution for 1 % and 2 % damping, 150-300 rad/s; resonances
near 1/5, 1/4 and 1/3 of the first bending frequency (832 rad/s) are marked.

Reads the results of ``sweeps/slider_crank.toml`` (computed and stored on first use), the
linearized curves. Red and blue: the full non-linear equations (4), 2 % and 1 % damping,
the branches of ``sweeps/slider_crank_nonlinear.toml`` and
``sweeps/slider_crank_nonlinear_1percent.toml`` (arc-length continuation of EGA-IHB with
Floquet multipliers): the midpoint deflection along each orbit through the non-linear
kinematics, as the studies store it (``output_samples`` times per period), solid stable, dashed unstable, folds marked. At 1 % the
resonance near omega1/3 bends backwards through two folds (a jump region, the middle
branch unstable), its peak at the upper fold. The 2 % curve has no fold: its peaks sit
slightly below the linearized ones and within a few rad/s of them (the one near omega1/4 at
a slightly higher speed, the one near omega1/3 at a slightly lower speed).

    python figures/fig05_slider_crank_max_deflection.py [OUT_DIR]
"""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.plotting import (drawn_branch, figure_group, figure_result, figure_study, plot_branch,  # noqa: E402
                               save_figure, unique_legend)


def max_deflection(harmonics: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """max |y| over one period per speed from harmonics (k, 2m+1) at indices l (2m+1,)."""
    theta = np.linspace(0.0, 2 * np.pi, 512, endpoint=False)
    return np.abs((harmonics @ np.exp(1j * np.outer(indices, theta))).real).max(axis=1)


def nonlinear_max_deflection(group) -> np.ndarray:
    """max |y| over one period of every orbit of a non-linear branch (k,), from the
    outputs its study stored (a branch group of the result)."""
    return np.abs(group["outputs"].sel(output="midpoint_deflection").values).max(axis=1)


NONLINEAR = {0.02: ("slider_crank_nonlinear", "C3"), 0.01: ("slider_crank_nonlinear_1percent", "C0")}


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = figure_result("slider_crank")
    w1 = float(ds["omega_over_omega1"].attrs["reference_frequency"])
    omega = ds["omega"].values
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for damping, style in ((0.01, "0.55"), (0.02, "k")):
        harmonics = ds["harmonics"].sel(damping=damping, output="midpoint_deflection").values  # (k, 2m+1)
        ax.plot(omega, max_deflection(harmonics, ds["harmonic"].values), "-", color=style, lw=1,
                label=f"{damping:.0%}, linearized")
    for damping, (name, color) in NONLINEAR.items():
        study = figure_study(name)
        if abs(study.parameters["damping"] - damping) > 1e-12:
            raise RuntimeError(f"sweeps/{name}.toml must have damping = {damping}, as Fig. 5")
        branch = drawn_branch(figure_result(name)["frequency"])  # every point kept, special points once
        plot_branch(ax, branch, None, f"{damping:.0%}, non-linear,", color=color, x=branch.omega,
                    y=nonlinear_max_deflection(figure_group(name, "frequency")))
    for k in (5, 4, 3):
        ax.axvline(w1 / k, color="0.6", ls=":", lw=0.8)
        ax.text(w1 / k, 0.02, f" $\\omega_1/{k}$", transform=ax.get_xaxis_transform(), ha="left", va="bottom",
                fontsize=8)
    ax.set_xlim(omega[0], omega[-1])
    ax.set_xlabel(r"$\omega$ [rad/s]")
    ax.set_ylabel("max midpoint deflection / rod length [-]")
    unique_legend(ax, fontsize=7, loc="upper left")
    fig.tight_layout()
    return [save_figure(fig, pathlib.Path(out_dir) / "fig05_slider_crank_max_deflection.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
