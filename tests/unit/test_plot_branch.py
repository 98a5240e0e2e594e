"""The branch drawing marks every kind of special point the continuation can report."""

from types import SimpleNamespace

import numpy as np

from periodyn.arclength import SpecialPoint
from periodyn.arclength.events import KINDS
from periodyn.plotting import plot_branch, plt


def test_plot_branch_marks_every_special_point_kind():
    omega = np.linspace(1.0, 2.0, 9)
    amplitude = np.column_stack([omega**2, omega])
    points = [SpecialPoint(type=kind, index=i + 1, omega=1.1 + 0.2 * i, parameter=1.1 + 0.2 * i,
                           amplitude=np.array([10.0 + i, 0.0])) for i, kind in enumerate(KINDS)]
    branch = SimpleNamespace(parameter=omega, amplitude=amplitude, special_points=points,
                             stable=[True] * 4 + [False] * 5)
    fig, ax = plt.subplots()
    plot_branch(ax, branch, 0)
    labels = ax.get_legend().get_texts()
    assert {t.get_text() for t in labels} >= set(KINDS) | {"stable", "unstable"}
    marked = [line for line in ax.get_lines() if len(line.get_xdata()) == 1]
    assert [float(line.get_ydata()[0]) for line in marked] == [10.0, 11.0, 12.0, 13.0]
    plt.close(fig)


def _loop_branch():
    """A period-doubled branch born at omega = 1 on its parent, turning at 0.5 (fold),
    rejoining the parent at omega = 2 (reported as a fold), then retracing the same
    amplitudes (the orbits shifted by T) back to the start."""
    from periodyn.arclength import Branch

    half = np.concatenate([np.linspace(1.0, 0.5, 6), np.linspace(0.5, 2.0, 16)[1:]])  # omega: 1 -> 0.5 -> 2
    n = half.size
    omega = np.concatenate([half, half[::-1][1:]])                                     # and back: 2n - 1 points
    amp = 1.0 + np.sin(np.linspace(0.0, np.pi, n))
    amplitude = np.concatenate([amp, amp[::-1][1:]])[:, None]
    k = omega.size
    fold = lambda i: SpecialPoint("fold", i, omega[i], omega[i], amplitude=amplitude[i])  # noqa: E731
    points = (fold(5), fold(n - 2), fold(2 * n - 7))  # 5 and 2n - 7 bracket the same point (omega, amplitude)
    branch = Branch(omega, omega, None, amplitude, np.ones(k, bool), np.ones(k), np.zeros(k), np.zeros(k), points,
                    tuple(range(k)), "")
    doublings = [SimpleNamespace(omega=1.0), SimpleNamespace(omega=omega[n - 2])]
    parent = SimpleNamespace(points=lambda kind: doublings if kind == "period-doubling" else [])
    return branch, parent, n


def test_drawn_branch_keeps_each_special_point_once_and_types_the_junctions_period_doubling():
    from periodyn.plotting import drawn_branch

    branch, parent, n = _loop_branch()
    alone = drawn_branch(branch)
    assert len(alone) == len(branch) and [p.index for p in alone.special_points] == [5, n - 2]
    drawn = drawn_branch(branch, parent=parent)
    assert len(drawn) == n and drawn.solutions == tuple(range(n)) and drawn.omega[-1] == 2.0
    assert [(p.type, p.index) for p in drawn.special_points] == [("fold", 5), ("period-doubling", n - 2)]
