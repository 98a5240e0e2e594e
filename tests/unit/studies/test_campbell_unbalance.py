"""Campbell studies with [[campbell.unbalance]]: the result file carries the synchronous
unbalance response (group "unbalance") equal to periodyn.rotor.unbalance_response, with
the damped critical speeds, and --plot draws the Campbell and Bode diagrams; bad tables
are refused naming the file."""

from __future__ import annotations

import numpy as np
import pytest

from periodyn.cli import main
from periodyn.errors import InputError
from periodyn.examples import rotor
from periodyn.rotor import Unbalance, critical_speeds, unbalance_response
from periodyn.studies.campbell import unbalance_result
from periodyn.studies.spec import load_sweep_file, project_root

ROTOR = project_root() / "sweeps" / "rotors" / "table1.toml"
STUDY = f"""
description = "unbalance response"
[model]
rotor = "{ROTOR.as_posix()}"
[campbell]
speeds = {{ start = 1000.0, stop = 24000.0, num = 24, unit = "rpm" }}
modes = 4
[[campbell.unbalance]]
station = 4
mass = 0.01
eccentricity = 0.01
[[campbell.unbalance]]
station = 5
mass = 0.005
eccentricity = 0.01
phase = 1.0
"""


def test_campbell_study_with_unbalance_writes_the_response_and_the_bode_figure(tmp_path, capsys):
    study = tmp_path / "u.toml"
    study.write_text(STUDY)
    out = tmp_path / "u.nc"
    assert main(["sweep", str(study), "--out", str(out), "--plot", str(tmp_path / "u.png")]) == 0
    assert "damped critical speeds 2130 rpm, 9881 rpm, 18684 rpm" in capsys.readouterr().out
    assert (tmp_path / "u.png").stat().st_size > 30_000
    response = unbalance_result(out)
    speeds = np.linspace(1000.0, 24000.0, 24) * np.pi / 30.0
    direct = unbalance_response(rotor(), [Unbalance(4, 0.01, 0.01), Unbalance(5, 0.005, 0.01, 1.0)], speeds)
    np.testing.assert_allclose(response["response"].values, direct["response"].values, rtol=1e-12)
    np.testing.assert_allclose(response.attrs["critical_speeds"], critical_speeds(rotor(), (speeds[0], speeds[-1])),
                               rtol=1e-12)
    plain = tmp_path / "plain.toml"
    plain.write_text(STUDY.split("[[campbell.unbalance]]")[0])
    assert main(["sweep", str(plain), "--out", str(tmp_path / "p.nc"), "-q"]) == 0
    assert unbalance_result(tmp_path / "p.nc") is None


@pytest.mark.parametrize("table, message", [
    ("[[campbell.unbalance]]\nstation = 4\nmass = -1.0\neccentricity = 0.01\n", "mass: must be"),
    ("[[campbell.unbalance]]\nstation = 4\nmass = 1.0\n", "missing|requires|eccentricity"),
    ("[[campbell.unbalance]]\nstation = 4\nmass = 1.0\neccentricity = 0.1\nphi = 1\n", "phi"),
    ("[campbell.grid]\nelements = [5, 10]\n[[campbell.unbalance]]\nstation = 4\nmass = 1.0\neccentricity = 0.1\n",
     "without \\[campbell.grid\\]"),
])
def test_bad_unbalance_tables_are_refused(tmp_path, table, message):
    study = tmp_path / "bad.toml"
    study.write_text(STUDY.split("[[campbell.unbalance]]")[0].replace(f'rotor = "{ROTOR.as_posix()}"',
                                                                     'example = "rotor"') + table)
    with pytest.raises(InputError, match=message):
        load_sweep_file(study)


def test_an_unbalance_off_the_rotor_names_the_file(tmp_path, capsys):
    study = tmp_path / "off.toml"
    study.write_text(STUDY.replace("station = 5", "station = 6"))
    assert main(["sweep", str(study), "--out", str(tmp_path / "off.nc"), "-q"]) == 2
    err = capsys.readouterr().err
    assert "off.toml: [[campbell.unbalance]]: unbalance station 6 is out of range" in err
