"""Every figure script ``figures/fig*.py`` runs from a fresh checkout (no results) on the
reduced studies of ``tests/data/figure_studies`` (fewer speeds, shorter branches; read
through ``periodyn.plotting.figure_study``/``figure_result`` with PERIODYN_FIGURE_STUDIES)
and writes its files into a temporary folder, so that no figure script breaks unnoticed.
The results are computed once, into a temporary folder shared by the scripts. The scripts
only read results and draw: none imports a computing module or builds a model (checked
statically, in a moment)."""

from __future__ import annotations

import ast
import importlib.util
import re
import sys
from pathlib import Path

import pytest

from periodyn.plotting import RESULTS_VARIABLE, STUDIES_VARIABLE
from periodyn.studies.spec import load_sweep_file

ROOT = Path(__file__).resolve().parents[2]
REDUCED = ROOT / "tests" / "data" / "figure_studies"
SCRIPTS = sorted((ROOT / "figures").glob("fig*.py"))


@pytest.fixture(scope="module")
def results(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("results")


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_figure_script_runs_on_the_reduced_studies(script, results, tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    monkeypatch.setenv(STUDIES_VARIABLE, str(REDUCED.relative_to(ROOT)))
    monkeypatch.setenv(RESULTS_VARIABLE, str(results))
    monkeypatch.syspath_prepend(str(ROOT / "figures"))  # scripts share helpers (fig09 -> fig10, 11, 12)
    monkeypatch.setattr(sys, "argv", [str(script)])
    spec = importlib.util.spec_from_file_location(f"figure_under_test_{script.stem}", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    paths = [Path(p) for p in module.main(tmp_path)]
    assert paths, f"{script.name} wrote nothing"
    for path in paths:
        assert path.parent == tmp_path and path.is_file() and path.stat().st_size > 0, path


def test_every_reduced_study_replaces_a_shipped_one_and_is_valid():
    reduced = sorted(REDUCED.glob("*.toml"))
    assert reduced
    for path in reduced:
        assert (ROOT / "sweeps" / path.name).is_file(), f"{path.name} replaces no study in sweeps/"
        assert load_sweep_file(path).kind == load_sweep_file(ROOT / "sweeps" / path.name).kind


def test_every_committed_figure_file_is_written_by_a_script():
    """A file in figures/png/ that no script names could only go stale."""
    named = set()
    for script in SCRIPTS:
        named |= set(re.findall(r'"([\w.]+\.(?:png|txt))"', script.read_text()))
    committed = {p.name for p in (ROOT / "figures" / "png").iterdir() if p.is_file()}
    assert committed <= named, f"no script writes {sorted(committed - named)}"


#: What a figure script may import from periodyn: the plotting helpers (which read results),
#: and the published numbers that a table prints beside the results (data, not computation).
READ_ONLY = {"periodyn.plotting": None,
             "periodyn.examples.rotor_table1": {"TABLE_I_PRESENT", "TABLE_I_REFERENCE", "TABLE_I_SPEED_RPM"}}
#: Calls that build or evaluate a model: a figure reads the parsed study file, never builds it.
COMPUTING_CALLS = {"build", "at", "builder"}


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_figure_scripts_only_read_results(script):
    """No import of a computing module (periodyn.nonlinear, numerics, examples, ...) and no
    model built: every number a figure draws is computed by a study and read from its result."""
    tree = ast.parse(script.read_text(), str(script))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                assert not alias.name.startswith("periodyn") or (alias.name in READ_ONLY
                                                                 and READ_ONLY[alias.name] is None), \
                    f"{script.name}:{node.lineno} imports {alias.name}"
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("periodyn"):
            allowed = READ_ONLY.get(node.module, set())
            names = {alias.name for alias in node.names}
            assert node.module in READ_ONLY and (allowed is None or names <= allowed), \
                f"{script.name}:{node.lineno} imports {sorted(names)} from {node.module}"
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            assert node.func.attr not in COMPUTING_CALLS, f"{script.name}:{node.lineno} calls .{node.func.attr}()"
