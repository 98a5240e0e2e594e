"""Result files: netCDF round trip, readable without periodyn, and config.ensure."""

from __future__ import annotations

import json
import sys

import h5py
import numpy as np
import pytest
import xarray as xr

from periodyn.errors import InputError
from periodyn.examples import pendulum
from periodyn.studies.spec import ensure
from periodyn.results import load, load_groups, save
from periodyn.engine.front import sweep

SWEEP_FILE = """
description = "tiny pendulum sweep for tests"
[model]
example = "pendulum"
[model.parameters]
zeta = 0.02
[sweep]
omega = { start = 0.2, stop = 1.2, num = 12, unit = "omega0" }
harmonics = 5
samples = 24
"""


@pytest.fixture(scope="module")
def result():
    return sweep(pendulum(samples=24), np.linspace(0.5, 4.0, 9), 5, progress=False)


def test_round_trip_is_exact(result, tmp_path):
    path = save(result, tmp_path / "r.nc")
    back = load(path)
    xr.testing.assert_identical(back, result)
    assert back["harmonics"].dtype == complex and back["stable"].dtype == bool
    assert json.loads(back.attrs["sweep_options"])["harmonics"] == 5


def test_file_opens_without_periodyn(result, tmp_path):
    path = save(result, tmp_path / "r.nc")
    with h5py.File(path, "r") as f:  # a plain HDF5/netCDF-4 reader: real arrays, named dimensions
        assert f["harmonics"].shape == (9, 11, 1, 2)
        assert f["harmonics"].dtype == np.float64
        np.testing.assert_array_equal(f["harmonics"][..., 1], result["harmonics"].values.imag)
        np.testing.assert_array_equal(f["omega"][...], result["omega"].values)
        assert f["omega"].attrs["units"] in (b"rad/s", "rad/s")
    raw = xr.open_dataset(path, engine="h5netcdf")
    assert raw["exponents"].dims == ("omega", "exponent", "part")
    raw.close()


def test_load_names_missing_and_broken_files(tmp_path):
    with pytest.raises(InputError, match="no result file"):
        load(tmp_path / "missing.nc")
    (tmp_path / "broken.nc").write_text("not netcdf")
    with pytest.raises(InputError, match="not a readable"):
        load(tmp_path / "broken.nc")


def test_save_leaves_no_partial_file(result, tmp_path):
    save(result, tmp_path / "a" / "r.nc")
    assert [p.name for p in (tmp_path / "a").iterdir()] == ["r.nc"]


def test_groups_round_trip_checksummed(result, tmp_path):
    """A file of several datasets (root + netCDF groups) round-trips exactly, every group's
    variables carry Fletcher-32 and one digest covers them all: a changed byte in a group is
    the same clear error as in a sweep file."""
    root = xr.Dataset(attrs={"what": "two sweeps"})
    path = save(root, tmp_path / "g.nc", {"a": result, "b": result.isel(omega=slice(0, 3))})
    back_root, groups = load_groups(path)
    assert back_root.attrs["what"] == "two sweeps" and set(groups) == {"a", "b"}
    xr.testing.assert_identical(groups["a"], result)
    xr.testing.assert_identical(groups["b"], result.isel(omega=slice(0, 3)))
    with h5py.File(path, "r+") as f:
        assert f["b/harmonics"].fletcher32
        f["b/residual"][0] += 1.0  # a consistent change: Fletcher-32 rewritten, the digest is not
    with pytest.raises(InputError, match=f"{path} is not a readable periodyn result file, or it is damaged.*SHA-256"):
        load_groups(path)


def test_ensure_computes_once_then_reads(tmp_path, monkeypatch):
    (tmp_path / "sweeps").mkdir()
    (tmp_path / "sweeps" / "tiny.toml").write_text(SWEEP_FILE)
    monkeypatch.chdir(tmp_path)
    first = ensure("tiny")
    assert (tmp_path / "results" / "tiny.nc").is_file()
    assert first.attrs["sweep_file_text"] == SWEEP_FILE
    np.testing.assert_allclose(first["omega_over_omega0"].values, np.linspace(0.2, 1.2, 12), rtol=1e-12)

    sweep_module = sys.modules["periodyn.engine.front"]
    monkeypatch.setattr(sweep_module, "sweep_file", lambda *a, **k: pytest.fail("recomputed an up-to-date result"))
    xr.testing.assert_identical(ensure("tiny"), first)
    monkeypatch.undo()

    monkeypatch.chdir(tmp_path)
    (tmp_path / "sweeps" / "tiny.toml").write_text(SWEEP_FILE.replace("num = 12", "num = 7"))
    assert ensure("tiny").sizes["omega"] == 7  # the sweep file changed: computed again


def test_to_dataset_lays_out_the_columns_it_defines():
    """empty_columns and to_dataset read one layout: every column becomes a variable with
    the point dimensions first, and the output units reach the attributes."""
    from periodyn.results import empty_columns, to_dataset

    columns = empty_columns(6, 2, 2, 4)
    ds = to_dataset(columns, omega=np.array([1.0, 2.0, 3.0]), harmonics=2, outputs=("x", "phi"),
                    output_units=("m", "rad"), grid={"zeta": np.array([0.1, 0.2])}, reference=("omega0", 2.0))
    assert set(columns) - {"index"} == set(ds.data_vars)
    assert ds["harmonics"].dims == ("zeta", "omega", "harmonic", "output") and ds.sizes["harmonic"] == 5
    assert ds["exponents"].dims == ("zeta", "omega", "exponent") and ds.sizes["exponent"] == 4
    assert list(ds["output_units"].values) == ["m", "rad"]
    assert ds["amplitude"].attrs["units"] == "per output: see output_units"
    assert (ds["status"].values == 1).all() and np.isnan(ds["amplitude"].values).all()
    np.testing.assert_allclose(ds["omega_over_omega0"].values, [0.5, 1.0, 1.5])
    same = to_dataset(columns, omega=np.array([1.0, 2.0, 3.0]), harmonics=2, outputs=("x", "phi"),
                      output_units=("m", "m"), grid={"zeta": np.array([0.1, 0.2])})
    assert same["mean"].attrs["units"] == "m"
