"""Axes helpers shared by every drawing: speed axis and output unit of a sweep, shading of
unstable spans, the grid points of a parameter grid, legends, saving."""

from __future__ import annotations

import itertools
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

__all__ = ["MAX_CURVES", "speed_axis", "output_unit", "unstable_spans", "shade_unstable", "grid_points", "save_figure", "unique_legend"]


MAX_CURVES = 12


def speed_axis(ds: xr.Dataset) -> tuple[np.ndarray, str]:
    """(speeds, axis label): omega/reference when the sweep has a reference frequency
    (its value in rad/s in the label), else omega in rad/s."""
    for name in ds.coords:
        if str(name).startswith("omega_over_"):
            reference = str(name)[len("omega_over_"):].replace("omega", "ω", 1)
            value = ds[name].attrs.get("reference_frequency")
            shown = f" ({reference} = {float(value):.4g} rad/s)" if value is not None else ""
            return ds[name].values, f"ω / {reference}{shown}"
    return ds["omega"].values, "ω [rad/s]"


def output_unit(ds: xr.Dataset) -> str:
    """The unit of the outputs when they share one ('' when unknown or mixed)."""
    if "output_units" not in ds.coords:
        return ""
    units = {str(u) for u in ds["output_units"].values}
    return units.pop() if len(units) == 1 else ""


def unstable_spans(x: np.ndarray, stable: np.ndarray) -> list[tuple[float, float]]:
    """Intervals [x_first, x_last] of consecutive unstable points, shape-(k,) inputs."""
    spans, start = [], None
    for xi, ok in zip(x, stable):
        if not ok and start is None:
            start = last = xi
        elif not ok:
            last = xi
        elif start is not None:
            spans.append((start, last))
            start = None
    if start is not None:
        spans.append((start, last))
    return spans


def shade_unstable(ax, x: np.ndarray, stable: np.ndarray, color: str = "0.88") -> None:
    """Grey bands behind the speeds where the periodic solution is unstable."""
    for a, b in unstable_spans(x, stable):
        ax.axvspan(a, b, color=color, lw=0, zorder=0)


def grid_points(ds: xr.Dataset) -> list[dict]:
    """Selectors of every parameter-grid point (``[{}]`` for a plain speed sweep)."""
    grid_dims = [d for d in ds["max_real_exponent"].dims if d != "omega"]
    return [dict(zip(grid_dims, vals)) for vals in itertools.product(*(ds[d].values for d in grid_dims))]


def save_figure(fig, path) -> Path:
    """Save ``fig`` to ``path`` (folders created) and close it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def unique_legend(ax, **kwargs) -> None:
    """A legend with one entry per label (branches draw one line per stability run)."""
    handles, labels = ax.get_legend_handles_labels()
    uniq = dict(zip(labels, handles))
    ax.legend(uniq.values(), uniq.keys(), **kwargs)
