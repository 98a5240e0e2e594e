"""Drawing sweep results (matplotlib, Agg backend): the ``periodyn sweep --plot`` figure
and small helpers the scripts in ``figures/`` share. Drawing only reads datasets and
branches; :func:`figure_result` runs a study whose result is missing or stale.

The figure scripts read their studies through :func:`figure_study` (the parsed study
file), :func:`figure_result` (its result, computed when not current) and
:func:`figure_group` (one group of a continuation result: a branch with its stored
outputs, or the time history). They only read and draw: every number they show is
computed by the study (``tests/integration/test_figures.py`` checks that no script
imports a computing module). Two environment variables choose where:

``PERIODYN_FIGURE_STUDIES``
    a folder of study files that replace those of ``sweeps/`` with the same name (a study
    it lacks is read from ``sweeps/``). ``tests/data/figure_studies`` holds reduced
    studies (fewer speeds, shorter branches) that make every figure in about a minute::

        PERIODYN_FIGURE_STUDIES=tests/data/figure_studies periodyn figures --out-dir /tmp/png

``PERIODYN_FIGURE_RESULTS``
    the folder of the results (default ``results/``, or ``results/<folder name>/`` with
    ``PERIODYN_FIGURE_STUDIES``, so that reduced results never replace full ones).

Relative folders are taken from the project root (the folder holding ``sweeps/``).
"""

from __future__ import annotations

import itertools
import textwrap
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

__all__ = ["STUDIES_VARIABLE", "RESULTS_VARIABLE", "figure_study", "figure_result", "figure_group", "speed_axis", "output_unit",
           "unstable_spans", "shade_unstable", "grid_points", "plot_sweep", "save_figure",
           "plot_branch", "drawn_branch", "unique_legend", "time_history_figure", "plot_study", "plot_transient",
           "plot_campbell", "plot_bode", "plot_stability_chart"]

_MAX_CURVES = 12

STUDIES_VARIABLE = "PERIODYN_FIGURE_STUDIES"
RESULTS_VARIABLE = "PERIODYN_FIGURE_RESULTS"


def _study_folders(name: str) -> tuple[Path, Path]:
    """(the folder holding ``<name>.toml``, the results folder) of the figure scripts."""
    import os

    from .studies.spec import project_root

    root = project_root()
    chosen = os.environ.get(STUDIES_VARIABLE, "")
    studies = root / chosen if chosen else root / "sweeps"
    if chosen and not studies.is_dir():
        from .errors import InputError

        raise InputError(f"{STUDIES_VARIABLE}={chosen}: no such folder (from {root}); give a folder of study files")
    results = os.environ.get(RESULTS_VARIABLE, "")
    results = root / results if results else root / "results" / (studies.name if chosen else "")
    return (studies if (studies / f"{name}.toml").is_file() else root / "sweeps"), results


def figure_study(name: str):
    """The parsed study file ``<name>.toml`` a figure reads (module docstring: where from)."""
    from .studies.spec import load_sweep_file

    return load_sweep_file(_study_folders(name)[0] / f"{name}.toml")


def figure_result(name: str):
    """The result of the study ``<name>`` (:func:`periodyn.studies.spec.ensure`: read when
    current, else computed): a Dataset, or {branch name: Branch} of a continuation."""
    from .studies.spec import ensure

    studies, results = _study_folders(name)
    return ensure(name, results, studies)


def figure_group(name: str, group: str) -> xr.Dataset:
    """The netCDF group ``group`` of the continuation study ``<name>``'s result (computed
    first when not current, as :func:`figure_result`): a branch ("frequency", ... with its
    ``outputs`` when the study stores them) or "time_history"."""
    from .errors import InputError
    from .results import load_groups

    figure_result(name)
    studies, results = _study_folders(name)
    path = results / f"{name}.nc"
    groups = load_groups(path)[1]
    if group not in groups:
        raise InputError(f"{path} has no group '{group}' (it has {', '.join(groups) or 'none'}); add what makes it "
                         f"to {studies / (name + '.toml')} (periodyn.studies.orbits)")
    return groups[group]


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
    curves = [(sel, out) for sel in grid_points(ds) for out in outputs][:_MAX_CURVES]
    for sel, out in curves:
        point = ds.sel(sel) if sel else ds
        amp = point["amplitude"].sel(output=out).values
        stable = point["stable"].values
        line, = top.semilogy(x, amp, lw=1.2, label=_label(sel, out, len(outputs) > 1))
        bad = ~stable & np.isfinite(amp)
        top.semilogy(x[bad], amp[bad], "x", ms=4, color=line.get_color())
    for sel in grid_points(ds)[:_MAX_CURVES]:
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


def save_figure(fig, path) -> Path:
    """Save ``fig`` to ``path`` (folders created) and close it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


_MARK = {"fold": ("o", "k"), "branch-point": ("D", "tab:green"), "period-doubling": ("s", "tab:red"), "neimark-sacker": ("^", "tab:purple")}


def plot_branch(ax, branch, coordinate: int | None, label: str = "", color: str = "tab:blue", x=None,
                y=None) -> None:
    """Amplitude of one coordinate along a branch: solid stable, dashed unstable, markers
    at special points (their refined amplitude). x: the abscissa per point (k,), default
    the branch's parameter; y: the ordinate per point (k,) instead of the amplitude of
    ``coordinate`` (then None). A special point sits where it lies between its two points
    (on y, interpolated likewise)."""
    xs = branch.parameter if x is None else np.asarray(x)
    amp = branch.amplitude[:, coordinate] if y is None else np.asarray(y)
    stable = np.array([bool(s) for s in branch.stable])
    starts = np.concatenate([[0], np.nonzero(np.diff(stable.astype(int)))[0] + 1])
    ends = np.concatenate([starts[1:], [len(amp) - 1]])
    for a, b in zip(starts, ends):  # runs of equal stability, overlapping by one point
        flag = stable[a]
        ax.plot(xs[a:b + 1], amp[a:b + 1], "-" if flag else "--", color=color,
                label=f"{label} {'stable' if flag else 'unstable'}".strip())
    for sp in branch.special_points:
        m, c = _MARK.get(sp.type, ("*", "tab:orange"))  # a user event
        ordinate = sp.amplitude[coordinate] if y is None else _special_abscissa(branch, sp, amp)
        ax.plot([_special_abscissa(branch, sp, xs)], [ordinate], m, color=c, mfc="none", ms=8, label=sp.type)
    unique_legend(ax, fontsize=7)


def drawn_branch(branch, parent=None, rtol: float = 1e-6):
    """``branch`` as it is drawn: each special point once (a branch that runs around a
    loop twice meets its points twice: same type, omega and amplitude within ``rtol``).

    parent: the period-1 branch that a period-doubled ``branch`` was switched from. Such
    a branch runs from a period-doubling point of ``parent`` to another (or back to the
    same), then retraces itself as the orbits shifted by one period T (the same
    amplitudes): it is cut where it first meets a period-doubling point of ``parent``,
    and its special points there, which continuation reports as folds (omega turns
    there), are typed "period-doubling", as they are on ``parent``."""
    from dataclasses import replace

    from .studies.orbits import first_pass, rejoining_points

    def same(a, b) -> bool:
        return abs(a - b) <= rtol * max(abs(a), abs(b))

    points = list(branch.special_points)
    end = len(branch.omega)
    if parent is not None:
        at_parent = rejoining_points(branch, parent, rtol)
        end = first_pass(branch, parent, rtol)
        points = [replace(p, type="period-doubling") if p in at_parent else p for p in points]
    kept = []
    for p in points:
        if p.index + 1 < end and not any(
                q.type == p.type and same(q.omega, p.omega) and np.allclose(q.amplitude, p.amplitude, rtol=rtol,
                                                                            atol=0) for q in kept):
            kept.append(p)
    cut = slice(0, end)
    columns = {name: getattr(branch, name)[cut] for name in ("omega", "parameter", "amplitude", "stable",
                                                             "max_multiplier", "residual", "iterations")}
    unknowns = None if branch.unknowns is None else branch.unknowns[cut]
    return replace(branch, **columns, solutions=tuple(branch.solutions[cut]), special_points=tuple(kept),
                   unknowns=unknowns)


def _special_abscissa(branch, point, xs: np.ndarray) -> float:
    """Where ``point`` lies on ``xs`` (k,): interpolated between its bracketing branch
    points by its parameter (a folded branch's parameter is not monotonic)."""
    i = min(max(point.index, 0), len(xs) - 2)
    p0, p1 = branch.parameter[i], branch.parameter[i + 1]
    t = 0.0 if p1 == p0 else float(np.clip((point.parameter - p0) / (p1 - p0), 0.0, 1.0))
    return float(xs[i] + t * (xs[i + 1] - xs[i]))


def unique_legend(ax, **kwargs) -> None:
    """A legend with one entry per label (branches draw one line per stability run)."""
    handles, labels = ax.get_legend_handles_labels()
    uniq = dict(zip(labels, handles))
    ax.legend(uniq.values(), uniq.keys(), **kwargs)


def time_history_figure(th: xr.Dataset, coords, lams, names, lam_names, title):
    """Two panels: q (coordinate names ``coords``) and lambda (constraint names ``lams``)
    of a study's "time_history" group: the orbit (lines) against the integrated motion
    (markers) over one period; ``names``/``lam_names`` label them."""
    fig, axes = plt.subplots(2, 1, figsize=(6.4, 6), sharex=True)
    for panel, variables, picked, labels in ((0, ("orbit_q", "q"), coords, names),
                                             (1, ("orbit_lambda", "lambda"), lams, lam_names)):
        dim = "coordinate" if panel == 0 else "constraint"
        for j, (c, label) in enumerate(zip(picked, labels)):
            orbit, integrated = (th[v].sel({dim: c}) for v in variables)
            axes[panel].plot(th["orbit_time"], orbit, color=f"C{j}", label=f"{label} {th.attrs['orbit_method'].upper()}")
            axes[panel].plot(th["time"], integrated, "o", color=f"C{j}", ms=3, mfc="none", label=f"{label} integration")
    axes[0].set_ylabel("q (m, rad)")
    axes[1].set_ylabel("lambda (N)")
    axes[1].set_xlabel("t (s)")
    for ax in axes:
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    axes[0].set_title(title, fontsize=9)
    fig.tight_layout()
    return fig


def plot_study(branches: dict, title: str = ""):
    """Bifurcation diagram: amplitude of the coordinate moving most vs omega (frequency and
    period-doubled branches) and vs the parameter (parameter curve); solid stable, dashed
    unstable, special points marked by type."""
    main = drawn_branch(branches["frequency"])
    j = int(main.amplitude.max(axis=0).argmax())
    coordinate = main.solutions[0].coordinate_names[j]
    panels = 2 if "parameter" in branches else 1
    fig, axes = plt.subplots(1, panels, figsize=(5.2 * panels, 4), squeeze=False)
    ax = axes[0, 0]
    plot_branch(ax, main, j, "period 1" if "period_doubled" in branches else "")
    if "period_doubled" in branches:
        doubled = drawn_branch(branches["period_doubled"], parent=main)
        plot_branch(ax, doubled, j, "period 2", color="tab:orange")
    ax.set_xlabel("omega (rad/s)")
    ax.set_ylabel(f"{coordinate} amplitude")
    if panels == 2:
        p = drawn_branch(branches["parameter"])
        plot_branch(axes[0, 1], p, j)
        axes[0, 1].set_xlabel(f"{p.parameter_name} at omega = {p.omega[0]:.4g} rad/s")
    for a in axes[0]:
        a.grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=9)
    fig.tight_layout()
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
    for colour, s in enumerate((ds["station"].values if stations is None else np.atleast_1d(stations))[:_MAX_CURVES]):
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
