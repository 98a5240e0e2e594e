"""Speed sweeps (the ``periodyn sweep --plot`` figure) and transients."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from .axes import MAX_CURVES, speed_axis, output_unit, shade_unstable, grid_points

__all__ = ["plot_sweep", "plot_transient"]


def _label(selector: dict, output: str, several_outputs: bool) -> str:
    parts = [f"{k} = {v:g}" if isinstance(v, (float, np.floating)) else f"{k} = {v}" for k, v in selector.items()]
    if several_outputs or not parts:
        parts.insert(0, output)
    return ", ".join(parts)


def plot_sweep(ds: xr.Dataset, title: str | None = None):
    """Amplitude per output vs speed (log scale, unstable points marked ×, failed points
    left out) over the largest real part of the characteristic exponents; unstable
    speeds shaded. The legend sits below the axes, off the data. Returns the Figure."""
    from matplotlib.patches import Patch

    x, xlabel = speed_axis(ds)
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(9, 6.5), height_ratios=(2, 1),
                                      layout="constrained")
    outputs = [str(o) for o in ds["output"].values]
    curves = [(sel, out) for sel in grid_points(ds) for out in outputs][:MAX_CURVES]
    for sel, out in curves:
        point = ds.sel(sel) if sel else ds
        amp = point["amplitude"].sel(output=out).values
        stable = point["stable"].values
        line, = top.semilogy(x, amp, lw=1.2, label=_label(sel, out, len(outputs) > 1))
        bad = ~stable & np.isfinite(amp)
        top.semilogy(x[bad], amp[bad], "x", ms=4, color=line.get_color())
    for sel in grid_points(ds)[:MAX_CURVES]:
        point = ds.sel(sel) if sel else ds
        bottom.plot(x, point["max_real_exponent"].values, lw=1.2,
                    label=_label(sel, "", False) if sel else None)
    handles, labels = top.get_legend_handles_labels()
    handles.append(top.plot([], [], "x", color="0.3")[0])
    labels.append("unstable point")
    if len(grid_points(ds)) == 1:
        shade_unstable(top, x, ds["stable"].values.reshape(-1))
        shade_unstable(bottom, x, ds["stable"].values.reshape(-1))
        handles.append(Patch(color="0.88"))
        labels.append("unstable band (max Re λ·T > 1e-6, or failed)")
    bottom.axhline(0.0, color="k", lw=0.7)
    unit = output_unit(ds)
    top.set_ylabel("amplitude, half peak-to-peak" + (f" [{'-' if unit == '1' else unit}]" if unit else ""))
    bottom.set_ylabel("max Re λ [1/s]")
    bottom.set_xlabel(xlabel)
    fig.legend(handles, labels, loc="outside lower center", ncols=min(len(labels), 4), fontsize=8)
    fig.suptitle(textwrap.fill(title or ds.attrs.get("title", "sweep"), 100), fontsize=9)
    top.grid(True, which="major", alpha=0.3)
    bottom.grid(True, alpha=0.3)
    return fig


def plot_transient(ds: xr.Dataset, title: str = ""):
    """The first output of a transient study's Dataset over time, per method, with its
    periodic part (dotted) when the study has one."""
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for method in ds["method"].values:
        ax.plot(ds["time"], ds["outputs"].sel({"method": method}).values[:, 0], label=str(method))
    if "periodic" in ds:
        ax.plot(ds["time"], ds["periodic"].values[:, 0], "k:", label="periodic")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(str(ds["output"].values[0]))
    ax.legend(fontsize=8)
    if title:
        ax.set_title(textwrap.fill(title, 90), fontsize=9)
    fig.tight_layout()
    return fig
