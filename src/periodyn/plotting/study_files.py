"""Where a figure script reads its study and its results: :func:`figure_study`,
:func:`figure_result` (computed by :func:`periodyn.studies.spec.ensure` when not current),
:func:`figure_group`, chosen by ``PERIODYN_FIGURE_STUDIES`` / ``PERIODYN_FIGURE_RESULTS``
(see :mod:`periodyn.plotting`)."""

from __future__ import annotations

from pathlib import Path

import xarray as xr

__all__ = ["STUDIES_VARIABLE", "RESULTS_VARIABLE", "figure_study", "figure_result", "figure_group"]


STUDIES_VARIABLE = "PERIODYN_FIGURE_STUDIES"


RESULTS_VARIABLE = "PERIODYN_FIGURE_RESULTS"


def _study_folders(name: str) -> tuple[Path, Path]:
    """(the folder holding ``<name>.toml``, the results folder) of the figure scripts."""
    import os

    from ..studies.spec import project_root

    root = project_root()
    chosen = os.environ.get(STUDIES_VARIABLE, "")
    studies = root / chosen if chosen else root / "sweeps"
    if chosen and not studies.is_dir():
        from ..errors import InputError

        raise InputError(f"{STUDIES_VARIABLE}={chosen}: no such folder (from {root}); give a folder of study files")
    results = os.environ.get(RESULTS_VARIABLE, "")
    results = root / results if results else root / "results" / (studies.name if chosen else "")
    return (studies if (studies / f"{name}.toml").is_file() else root / "sweeps"), results


def figure_study(name: str):
    """The parsed study file ``<name>.toml`` a figure reads (module docstring: where from)."""
    from ..studies.spec import load_sweep_file

    return load_sweep_file(_study_folders(name)[0] / f"{name}.toml")


def figure_result(name: str):
    """The result of the study ``<name>`` (:func:`periodyn.studies.spec.ensure`: read when
    current, else computed): a Dataset, or {branch name: Branch} of a continuation."""
    from ..studies.spec import ensure

    studies, results = _study_folders(name)
    return ensure(name, results, studies)


def figure_group(name: str, group: str) -> xr.Dataset:
    """The netCDF group ``group`` of the continuation study ``<name>``'s result (computed
    first when not current, as :func:`figure_result`): a branch ("frequency", ... with its
    ``outputs`` when the study stores them) or "time_history"."""
    from ..errors import InputError
    from ..results import load_groups

    figure_result(name)
    studies, results = _study_folders(name)
    path = results / f"{name}.nc"
    groups = load_groups(path)[1]
    if group not in groups:
        raise InputError(f"{path} has no group '{group}' (it has {', '.join(groups) or 'none'}); add what makes it "
                         f"to {studies / (name + '.toml')} (periodyn.studies.orbits)")
    return groups[group]
