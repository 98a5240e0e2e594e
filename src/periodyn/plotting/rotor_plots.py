"""Rotors: Campbell diagram (with unbalance-response peaks) and Bode plots."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from .axes import MAX_CURVES

__all__ = ["plot_campbell", "plot_bode"]


def plot_campbell(ds: xr.Dataset, title: str = "", unbalance: xr.Dataset | None = None):
    """Campbell diagram of one rotor (a Campbell Dataset without grid dimensions):
    stationary-frame whirl frequencies (cycles/min) over spin speed (rpm), forward and
    backward whirl in two colours, markers growing as the damping ratio falls, 1x and 2x
    running-speed lines and the stability threshold in the title; below, the Bode diagram
    (:func:`plot_bode`) of ``unbalance``, a synchronous response over the same speeds."""
    rows = (1,) if unbalance is None else (3, 2, 1.4)
    fig, axes = plt.subplots(len(rows), 1, squeeze=False, sharex=True, height_ratios=rows,
                             figsize=(6.5, 4.5) if unbalance is None else (7.5, 10))
    ax, *bode = axes[:, 0]
    rpm = ds["speed_rpm"].values
    freq = ds["frequency"].values * 30.0 / np.pi           # rad/s -> cycles per minute
    zeta = np.nan_to_num(ds["damping_ratio"].values)
    forward = ds["whirl"].values == "forward"
    size = 4.0 + 30.0 * (1.0 - np.clip(zeta / max(zeta.max(), 1e-12), 0.0, 1.0))
    every = slice(None, None, max(1, len(rpm) // 100))
    r = np.broadcast_to(rpm[:, None], freq.shape)
    for mask, colour, label in ((forward, "C3", "forward whirl"), (~forward, "C0", "backward whirl")):
        ax.scatter(r[every][mask[every]], freq[every][mask[every]], s=size[every][mask[every]], c=colour, lw=0,
                   label=label)
    for k in (1, 2):
        ax.plot(rpm, k * rpm, "k--" if k == 1 else "k:", lw=0.8, label=f"{k}x running speed")
    threshold = float(ds["threshold_speed"])
    note = (f"stability threshold {threshold * 30 / np.pi:.0f} rpm" if np.isfinite(threshold)
            else "stable over the whole speed range")
    ax.set_title(textwrap.fill(f"{title + ': ' if title else ''}{note}; larger markers = less damped", 90),
                 fontsize=9)
    ax.set(xlabel="" if bode else "spin speed [rpm]", ylabel="whirl frequency [cycles/min]")
    if rpm[-1] > rpm[0]:
        ax.set_xlim(rpm[0], rpm[-1])
    ax.set_ylim(0.0, 1.05 * max(freq.max(), 1.0))
    ax.legend(fontsize=8, loc="upper left")
    if unbalance is not None:
        plot_bode(unbalance, axes=bode)
    fig.tight_layout()
    return fig


def plot_bode(ds: xr.Dataset, title: str = "", stations=None, axes=None):
    """Bode diagram of a synchronous response (:func:`periodyn.rotor.response.unbalance_response`):
    amplitude |X| (log) and phase arg X (degrees) of the y (solid) and z (dashed) motion of
    ``stations`` (indices, default all) over spin speed (rpm), attribute ``critical_speeds``
    (rad/s) dotted; into ``axes`` (amplitude, phase), else a new Figure that it returns."""
    fig, (amplitude, phase) = (None, axes) if axes is not None else plt.subplots(
        2, 1, figsize=(7.5, 6.5), sharex=True, height_ratios=(2, 1.4))
    rpm = ds["speed_rpm"].values
    for colour, s in enumerate((ds["station"].values if stations is None else np.atleast_1d(stations))[:MAX_CURVES]):
        for direction, style in (("y", "-"), ("z", "--")):
            point = {"station": s, "direction": direction}
            amplitude.semilogy(rpm, ds["amplitude"].sel(point).values, style, color=f"C{colour}", lw=1.1, label=(
                f"station {s} ({float(ds['station_position'].sel(station=s)):.4g} m)" if direction == "y" else None))
            phase.plot(rpm, np.degrees(ds["phase"].sel(point).values), style, color=f"C{colour}", lw=1.1)
    for k, speed in enumerate(np.atleast_1d(ds.attrs.get("critical_speeds", []))):
        for ax in (amplitude, phase):
            ax.axvline(float(speed) * 30.0 / np.pi, color="0.4", lw=0.8, ls=":",
                       label="damped critical speed" if k == 0 and ax is amplitude else None)
    amplitude.set_title(textwrap.fill(f"synchronous response to {ds.attrs.get('load', 'a load')}", 110), fontsize=8)
    amplitude.set_ylabel("amplitude |X| [m]: y solid, z dashed")
    phase.set(ylabel="phase [deg]", yticks=[-180, -90, 0, 90, 180], xlabel="spin speed [rpm]", xlim=(rpm[0], rpm[-1]))
    amplitude.legend(fontsize=7, ncols=2)
    amplitude.grid(True, alpha=0.3), phase.grid(True, alpha=0.3)
    if fig is not None:
        fig.suptitle(textwrap.fill(title, 100), fontsize=9)
        fig.tight_layout()
    return fig
