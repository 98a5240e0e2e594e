"""The [chart] study kind (periodyn.studies.chart): its table is validated with messages
naming the fix, and ``periodyn sweep`` runs it into a result file that holds the chart a
direct call computes, prints its tips and draws it; ``--resume`` reads a current result."""

from __future__ import annotations

import numpy as np
import pytest

from periodyn.cli import main
from periodyn.errors import InputError
from periodyn.examples import pendulum
from periodyn.results import load
from periodyn.stability.chart_data import ChartOptions, chart_from_dataset
from periodyn.stability.charts import stability_chart
from periodyn.studies.spec import parse_sweep

STUDY = """
[model]
example = "pendulum"
[model.parameters]
eccentricity = 0.5
[chart]
parameter = {{ name = "zeta", {grid} }}
omega = {{ start = 0.8, stop = 1.5, num = 15, unit = "omega0" }}
harmonics = 8
samples = 32
{extra}
"""


def study(grid="start = 0.01, stop = 0.08, num = 4", extra="checks = 1"):
    return STUDY.format(grid=grid, extra=extra)


@pytest.mark.parametrize("grid, extra, message", [
    ('start = 0.01, stop = 0.08, num = 4', 'seeds = [0.02]', "not values of the parameter grid"),
    ('values = [0.02, 0.01]', '', "must increase"),
    ('start = 0.01, stop = 0.08, num = 4', 'stability = "newton"', "unknown method 'newton'"),
    ('start = 0.01, stop = 0.08, num = 4', 'xtol = 0.1', "must be below 1e-2"),
    ('values = [0.01, 0.02], start = 0.0', '', "unknown key 'start'"),
])
def test_bad_chart_tables_name_the_fix(grid, extra, message):
    with pytest.raises(InputError, match=message):
        parse_sweep(study(grid, extra), "c.toml")


def test_the_parameter_must_be_a_numeric_builder_keyword():
    with pytest.raises(InputError, match="'zeta_' is not a numeric parameter of pendulum; choose one of: length"):
        parse_sweep(study().replace('name = "zeta"', 'name = "zeta_"'), "c.toml")
    with pytest.raises(InputError, match="eccentricity is the chart's parameter"):
        parse_sweep(study().replace('name = "zeta"', 'name = "eccentricity"'), "c.toml")


def test_sweep_command_runs_a_chart_study_as_a_direct_call(tmp_path, capsys):
    path, out = tmp_path / "chart.toml", tmp_path / "chart.nc"
    path.write_text(study())
    assert main(["sweep", str(path), "--out", str(out), "--plot", str(tmp_path / "chart.png")]) == 0
    printed = capsys.readouterr().out
    assert "tip zeta = 0.0612" in printed and "monodromy checks: 2 of 2 agree" in printed
    assert (tmp_path / "chart.png").stat().st_size > 0
    ds = load(out)
    w0 = np.sqrt(9.81)
    assert ds.attrs["reference_frequency"] == pytest.approx(w0, rel=1e-15) and ds.attrs["omega_unit"] == "omega0"
    direct = stability_chart(lambda z: pendulum(zeta=z, eccentricity=0.5, samples=32), np.linspace(0.8, 1.5, 15) * w0,
                             np.linspace(0.01, 0.08, 4), ChartOptions(8), name="zeta")
    for a, b in zip(chart_from_dataset(ds).boundaries, direct.boundaries, strict=True):
        np.testing.assert_array_equal(a.omega, b.omega)
        np.testing.assert_array_equal(a.parameter, b.parameter)
    stamp = out.stat().st_mtime_ns
    assert main(["sweep", str(path), "--out", str(out), "-q", "--resume"]) == 0 and out.stat().st_mtime_ns == stamp
    assert main(["sweep", str(path), "--out", str(out), "-q", "--omega", "1:2:3"]) == 2
    assert "drop --omega" in capsys.readouterr().err
