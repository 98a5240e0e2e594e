"""Two-parameter stability charts: boundaries typed by how stability is lost."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from .axes import unique_legend

__all__ = ["plot_stability_chart"]


_KIND_COLOURS = {"fold": "tab:blue", "period-doubling": "tab:red", "neimark-sacker": "tab:green"}


def plot_stability_chart(ds: xr.Dataset, title: str = "", ax=None):
    """A stability chart (the result of a ``[chart]`` study, :mod:`periodyn.stability.chart_data`):
    each boundary in the (omega, parameter) plane, its points coloured by crossing type with
    short ticks towards the unstable side, tips (a zone closing) as triangles, monodromy
    checks as open squares (red crosses where they disagree); into ``ax``, else a new Figure that it returns."""
    from matplotlib.collections import LineCollection

    fig, ax = plt.subplots(figsize=(7, 4.8)) if ax is None else (None, ax)
    ref, unit = float(ds.attrs.get("reference_frequency", 1.0)), str(ds.attrs.get("omega_unit", "rad/s"))
    tick = 0.012 * np.ptp(ds["omega_grid"].values) / ref
    w, p, kind, side, curve = (ds[v].values for v in ("omega", "parameter", "kind", "side", "curve"))
    w = w / ref
    for i in range(ds.sizes["boundary"]):
        ax.plot(w[curve == i], p[curve == i], color="0.35", lw=0.9, zorder=1)
    for k in dict.fromkeys(map(str, kind)):
        mine = (kind == k) & (side != 0)
        ax.plot(w[mine], p[mine], "o", ms=3, color=_KIND_COLOURS.get(k, "k"), label=k, zorder=2)
        ax.add_collection(LineCollection([[(x, y), (x - s * tick, y)] for x, y, s in zip(w[mine], p[mine], side[mine])],
                                         colors=_KIND_COLOURS.get(k, "k"), linewidths=0.8))
    ax.plot(w[side == 0], p[side == 0], "k^", ms=6, label="tip: the zone closes", zorder=3)
    if ds.sizes.get("check", 0):
        ok = ds["check_agrees"].values
        for agrees, style in ((True, dict(marker="s", mfc="none", mec="k")), (False, dict(marker="X", color="r"))):
            if (ok == agrees).any():
                ax.plot(ds["check_omega"].values[ok == agrees] / ref, ds["check_parameter"].values[ok == agrees],
                        ls="none", ms=8, zorder=4, label=f"monodromy check {'agrees' if agrees else 'disagrees'}",
                        **style)
    ax.set(xlabel="ω [rad/s]" if unit == "rad/s" else f"ω / {unit.replace('omega', 'ω')}",
           ylabel=str(ds.attrs["parameter_name"]).replace("alpha", "α").replace("zeta", "ζ"),
           xlim=ds["omega_grid"].values[[0, -1]] / ref, ylim=ds["parameter_grid"].values[[0, -1]])
    ax.set_title(textwrap.fill(title + " (ticks: unstable side)", 100), fontsize=7)
    ax.grid(True, alpha=0.3)
    unique_legend(ax, fontsize=7)
    if fig is not None:
        fig.tight_layout()
    return fig
