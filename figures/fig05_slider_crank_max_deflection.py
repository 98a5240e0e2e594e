"""Fig. 5 of Schwab & Meijaard (2001): maximal dimensionless midpoint deflection of the
slider-crank's periodic solution for 1 % and 2 % damping, 150-300 rad/s; resonances
near 1/5, 1/4 and 1/3 of the first bending frequency (832 rad/s) are marked.

Reads the results of ``sweeps/slider_crank.toml`` (computed and stored on first use).
Dashed: the full non-linear equations (4), 2 % damping, from the branch of
``sweeps/slider_crank_nonlinear.toml``: the midpoint deflection along each stored orbit
(64 samples) through the non-linear kinematics; the peaks lean to lower speeds
(backward bending) and sit below the linearized ones."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.nonlinear import element_outputs  # noqa: E402
from periodyn.plotting import figure_result, figure_study, save_figure  # noqa: E402


def max_deflection(harmonics: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """max |y| over one period per speed from harmonics (k, 2m+1) at indices l (2m+1,)."""
    theta = np.linspace(0.0, 2 * np.pi, 512, endpoint=False)
    return np.abs((harmonics @ np.exp(1j * np.outer(indices, theta))).real).max(axis=1)


def nonlinear_max_deflection(branch, model, samples: int = 64) -> np.ndarray:
    """max |y| over one period of every orbit of a non-linear branch (k,)."""
    out = np.empty(len(branch.omega))
    for k, (omega, orbit) in enumerate(zip(branch.omega, branch.solutions)):
        t = np.arange(samples) * orbit.period / samples
        out[k] = np.abs(element_outputs(model, omega, t, orbit(t))[:, 0]).max()
    return out


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = figure_result("slider_crank")
    w1 = float(ds["omega_over_omega1"].attrs["reference_frequency"])
    omega = ds["omega"].values
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for damping, style in ((0.01, "C0-"), (0.02, "k-")):
        harmonics = ds["harmonics"].sel(damping=damping, output="midpoint_deflection").values  # (k, 2m+1)
        ax.plot(omega, max_deflection(harmonics, ds["harmonic"].values), style, lw=1, label=f"{damping:.0%} damping")
    branch = figure_result("slider_crank_nonlinear")["frequency"]
    study = figure_study("slider_crank_nonlinear")
    model = study.build().equations.model  # the element model the branch was computed for
    ax.plot(branch.omega, nonlinear_max_deflection(branch, model), "k--", lw=1,
            label=f"{study.parameters['damping']:.0%}, full non-linear")
    for k in (5, 4, 3):
        ax.axvline(w1 / k, color="0.6", ls=":", lw=0.8)
        ax.text(w1 / k, ax.get_ylim()[1] * 0.95, f"$\\omega_1/{k}$", ha="center", va="top", fontsize=8)
    ax.set_xlabel(r"$\omega$ [rad/s]")
    ax.set_ylabel("max midpoint deflection / rod length [-]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return [save_figure(fig, pathlib.Path(out_dir) / "fig05_slider_crank_max_deflection.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
