"""Drawing helpers for the DAE figure scripts (``figures/fig_dae_*.py``): response curves
with stable/unstable parts and special points, and time histories against integration."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_branch", "time_history_figure"]

_MARK = {"fold": ("o", "k"), "period-doubling": ("s", "tab:red"), "neimark-sacker": ("^", "tab:purple")}


def plot_branch(ax, branch, coordinate: int, label: str = "", color: str = "tab:blue", x=None) -> None:
    """Amplitude of one coordinate along a branch: solid stable, dashed unstable, markers
    at special points (their refined amplitude)."""
    xs = branch.parameter if x is None else x
    amp = branch.amplitude[:, coordinate]
    stable = np.array([bool(s) for s in branch.stable])
    starts = np.concatenate([[0], np.nonzero(np.diff(stable.astype(int)))[0] + 1])
    ends = np.concatenate([starts[1:], [len(amp) - 1]])
    for a, b in zip(starts, ends):  # runs of equal stability, overlapping by one point
        flag = stable[a]
        ax.plot(xs[a:b + 1], amp[a:b + 1], "-" if flag else "--", color=color,
                label=f"{label} {'stable' if flag else 'unstable'}".strip())
    for sp in branch.special_points:
        m, c = _MARK[sp.type]
        v = sp.parameter if x is None else np.interp(sp.parameter, branch.parameter, xs)
        ax.plot([v], [sp.amplitude[coordinate]], m, color=c, mfc="none", ms=8, label=sp.type)
    handles, labels = ax.get_legend_handles_labels()
    uniq = dict(zip(labels, handles))
    ax.legend(uniq.values(), uniq.keys(), fontsize=7)


def time_history_figure(sol, th, coords, lams, names, lam_names, title):
    """Two panels: q (coordinates ``coords``) and lambda (``lams``) of a PeriodicSolution
    (lines) against an integrated TimeHistory ``th`` (markers) over one period."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(6.4, 6), sharex=True)
    t = np.linspace(th.t[0], th.t[-1], 400)
    for j, c in enumerate(coords):
        axes[0].plot(t, sol(t)[:, c], color=f"C{j}", label=f"{names[j]} IHB")
        axes[0].plot(th.t, th.q[:, c], "o", color=f"C{j}", ms=3, mfc="none", label=f"{names[j]} integration")
    for j, c in enumerate(lams):
        axes[1].plot(t, sol.lam(t)[:, c], color=f"C{j}", label=f"{lam_names[j]} IHB")
        axes[1].plot(th.t, th.lam[:, c], "o", color=f"C{j}", ms=3, mfc="none", label=f"{lam_names[j]} integration")
    axes[0].set_ylabel("q (m, rad)")
    axes[1].set_ylabel("lambda (N)")
    axes[1].set_xlabel("t (s)")
    for ax in axes:
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    axes[0].set_title(title, fontsize=9)
    fig.tight_layout()
    return fig
