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

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .study_files import RESULTS_VARIABLE, STUDIES_VARIABLE, figure_group, figure_result, figure_study  # noqa: E402
from .axes import (grid_points, output_unit, save_figure, shade_unstable, speed_axis, unique_legend,  # noqa: E402
                   unstable_spans)
from .sweep_plots import plot_sweep, plot_transient  # noqa: E402
from .branch_plots import drawn_branch, plot_branch, plot_study, time_history_figure  # noqa: E402
from .rotor_plots import plot_bode, plot_campbell  # noqa: E402
from .chart_plots import plot_stability_chart  # noqa: E402

__all__ = ["STUDIES_VARIABLE", "RESULTS_VARIABLE", "figure_study", "figure_result", "figure_group", "speed_axis", "output_unit",
           "unstable_spans", "shade_unstable", "grid_points", "plot_sweep", "save_figure",
           "plot_branch", "drawn_branch", "unique_legend", "time_history_figure", "plot_study", "plot_transient",
           "plot_campbell", "plot_bode", "plot_stability_chart", "plt"]
