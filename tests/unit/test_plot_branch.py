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
