"""Fig. 9 of Schwab & Meijaard (2001): maximal dimensionless midpoint deflection of the
Cardan drive shaft's periodic solution in the lateral plane, max sqrt(v^2 + w^2)/l over one
period, over 0 < omega/omega_b < 1 (alpha = pi/6), the unstable stretches drawn thin
between circles; resonances near 1/4, 1/3 and 1/2 of omega_b are marked. v and w are the
outputs ``midpoint_deflection`` (along the yoke-pin direction) and
``midpoint_deflection_normal`` (the other lateral direction); with ``--components`` the
maxima of |v| and |w| are drawn too (dashed and dotted; either alone is a projection of
the lateral motion and can dip where the motion turns away from its direction).

Reads the results of ``sweeps/cardan_shaft.toml`` (computed and stored on first use).
Squares: the full non-linear equations (4) at twelve speeds, from the orbits of
``sweeps/cardan_shaft_nonlinear.toml`` (implicit shooting), the lateral deflection along
each orbit through the non-linear kinematics; filled stable, open unstable by the
multipliers of the shooting monodromy. The study stores those outputs along each orbit
(``output_samples = 360`` times per period); the figures only take their maxima.

    python figures/fig09_cardan_max_deflection.py [OUT_DIR] [--components]
"""

from __future__ import annotations

import json
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.plotting import figure_group, figure_result, save_figure  # noqa: E402

NAME = "cardan_shaft"
NONLINEAR = "cardan_shaft_nonlinear"
LATERAL = ("midpoint_deflection", "midpoint_deflection_normal")  # v, w over the length


def over_period(ds, output: str) -> np.ndarray:
    """The output over one period per speed, (k, 720), from its harmonics (l = -m..m)."""
    harmonics = ds["harmonics"].sel(output=output).values          # (k, 2m+1)
    theta = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    return (harmonics @ np.exp(1j * np.outer(ds["harmonic"].values, theta))).real


def speed_ratio(ds) -> np.ndarray:
    """omega / omega_b of the sweep (omega_b: the model's first bending frequency)."""
    return ds["omega_over_omega_b"].values


def draw_with_unstable(ax, ratio, values, unstable):
    """Stable stretches thick, unstable thin between circles at their ends."""
    ax.plot(ratio, np.where(unstable, np.nan, values), "k-", lw=1.2)
    ax.plot(ratio, np.where(unstable, values, np.nan), "k-", lw=0.5)
    edges = np.flatnonzero(np.diff(unstable.astype(int)))
    for i in edges:
        j = i + 1 if unstable[i + 1] else i
        ax.plot(ratio[j], values[j], "o", mfc="none", mec="k", ms=5)


def maximum_figure(ds, values, ylabel: str, title: str):
    """(figure, axes) of a maximum over the speed ratio: log scale, unstable stretches thin,
    1/4, 1/3, 1/2 of omega_b dotted."""
    fig, ax = plt.subplots(figsize=(6, 3.5))
    draw_with_unstable(ax, speed_ratio(ds), values, ds["stable"].values == 0)
    ax.set_yscale("log")
    for k in (4, 3, 2):
        ax.axvline(1 / k, color="0.6", ls=":", lw=0.8)
    ax.set_xlim(0, 1)
    ax.set_xlabel(r"$\omega/\omega_b$ [-]")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    return fig, ax


def lateral_maximum(ds) -> np.ndarray:
    """max over one period of the lateral deflection sqrt(v^2 + w^2) per speed, (k,)."""
    v, w = (over_period(ds, output) for output in LATERAL)
    return np.hypot(v, w).max(axis=1)


def nonlinear_points() -> dict[str, np.ndarray]:
    """The non-linear orbits of ``sweeps/cardan_shaft_nonlinear.toml``: omega / omega_b,
    stable (bool), and per orbit the maxima over one period of the lateral deflection
    sqrt(v^2 + w^2) (``lateral``) and of the twist (``twist``) from the outputs the study
    stored (measured from the rigid motion as the linearized outputs are), (k,) each."""
    group = figure_group(NONLINEAR, "frequency")
    outputs = group["outputs"]                                      # (point, sample, output)
    lateral = np.hypot(*(outputs.sel(output=output).values for output in LATERAL)).max(axis=1)
    omega_b = json.loads(group.attrs["model_metadata"])["omega_b"]  # the model's first bending frequency
    return {"ratio": group["omega"].values / omega_b, "stable": group["stable"].values == 1,
            "lateral": lateral, "twist": outputs.sel(output="twist").values.max(axis=1)}


def draw_nonlinear(ax, points: dict, key: str, legend: str = "lower left") -> None:
    """The non-linear maxima ``points[key]`` as squares: filled stable, open unstable;
    legend: its matplotlib location."""
    for stable, face, label in ((True, "k", "non-linear, stable"), (False, "none", "non-linear, unstable")):
        pick = points["stable"] == stable
        if pick.any():
            ax.plot(points["ratio"][pick], points[key][pick], "s", mfc=face, mec="k", ms=4, label=label)
    ax.legend(fontsize=7, loc=legend)


def main(out_dir: pathlib.Path, components: bool = False) -> list[pathlib.Path]:
    """Fig. 9 into ``out_dir``; components: also the maxima of |v| and |w|."""
    ds = figure_result(NAME)
    fig, ax = maximum_figure(ds, lateral_maximum(ds), r"$(\sqrt{v^2 + w^2}/l)_{max}$ [-]",
                             r"Cardan shaft, $\alpha = \pi/6$: midpoint deflection in the lateral plane "
                             "(squares: non-linear)")
    if components:
        ratio = speed_ratio(ds)
        labels = ("$|v/l|_{max}$ (yoke-pin direction)", "$|w/l|_{max}$ (normal to it)")
        for output, style, label in zip(LATERAL, ("--", ":"), labels):
            ax.plot(ratio, np.abs(over_period(ds, output)).max(axis=1), style, color="0.45", lw=0.8, label=label)
    draw_nonlinear(ax, nonlinear_points(), "lateral")
    fig.tight_layout()
    return [save_figure(fig, pathlib.Path(out_dir) / "fig09_cardan_max_deflection.png")]


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--components"]
    print(*main(pathlib.Path(args[0]) if args else pathlib.Path(__file__).parent / "png",
                components="--components" in sys.argv[1:]), sep="\n")
