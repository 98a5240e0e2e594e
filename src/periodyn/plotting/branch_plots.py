"""Continuation branches: amplitude with stability (solid/dashed) and special points,
bifurcation diagrams of a study, time histories of an orbit against integration."""

from __future__ import annotations


import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from .axes import unique_legend

__all__ = ["plot_branch", "drawn_branch", "time_history_figure", "plot_study"]


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

    from ..studies.orbits import first_pass, rejoining_points

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
