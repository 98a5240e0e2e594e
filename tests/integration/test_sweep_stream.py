"""Results streamed to the output (OutputOptions(stream=True)): the file written block by
block from the checkpoint chunks equals, value for value and attribute for attribute, the one
assembled in memory, with failed points (their messages), a parameter grid, blocks that cut
across chunks, and a resume after an interrupt; local workers write their own chunks, streamed
or not."""

from __future__ import annotations

import dask.array as da
import numpy as np
import pytest
import xarray as xr

from periodyn.engine import stream
from periodyn.engine.front import ExecutionOptions, OutputOptions, sweep
from periodyn.errors import ConvergenceError
from periodyn.examples import pendulum
from periodyn.results import load
from tests.integration.datasets import without_attrs

W0 = np.sqrt(9.81)
OMEGA = W0 * np.linspace(0.1, 1.4, 13)
GRID = {"eccentricity": [0.3, 0.5, 0.6]}
CHUNKS = ExecutionOptions(chunk_size=5)


def flaky(eccentricity):
    """The pendulum, failing (with a message of its own) at some speeds of one grid point."""
    model = pendulum(samples=24, eccentricity=eccentricity)

    def at(omega):
        if eccentricity == 0.5 and 2.0 < omega < 3.0:
            raise ConvergenceError(f"Newton did not converge at {omega:.3f} (\u03c9 test)", residual=1.0,
                                   iterations=50)
        return model.at(omega)

    return at


def file_without_time(path) -> xr.Dataset:
    ds = load(path)
    del ds.attrs["elapsed_s"]
    return ds


@pytest.mark.parametrize("block", [7, 1 << 13])  # blocks across chunks and grid rows; one block
def test_streamed_file_equals_the_file_assembled_in_memory(tmp_path, monkeypatch, block):
    monkeypatch.setattr(stream, "BLOCK_POINTS", block)
    kept = sweep(flaky, OMEGA, 4, parameters=GRID, out=tmp_path / "memory.nc", execution=CHUNKS, progress=False,
                 output=OutputOptions(stream=False))
    streamed = sweep(flaky, OMEGA, 4, parameters=GRID, out=tmp_path / "streamed.nc", execution=CHUNKS,
                     progress=False, output=OutputOptions(stream=True))
    assert isinstance(streamed["amplitude"].data, da.Array)  # read from the file when used
    failed = kept["status"].values != 0
    assert 0 < failed.sum() == streamed.attrs["failed_points"] == kept.attrs["failed_points"]
    assert all("\u03c9 test" in m for m in streamed["message"].values[failed])
    xr.testing.assert_identical(file_without_time(tmp_path / "streamed.nc"),
                                file_without_time(tmp_path / "memory.nc"))
    xr.testing.assert_identical(without_attrs(streamed), without_attrs(kept))


def test_block_chunks_are_contiguous_runs_of_points():
    for shape in [(13,), (3, 13), (4, 5, 6), (2, 1, 40)]:
        for target in (1, 7, 30, 1000):
            axis, chunks = stream._block_chunks(shape, target)
            assert all(sum(c) == n for c, n in zip(chunks, shape))
            assert all(c == (n,) for c, n in zip(chunks[axis + 1:], shape[axis + 1:]))
            assert all(set(c) == {1} for c in chunks[:axis])
            assert max(chunks[axis]) * int(np.prod(shape[axis + 1:])) <= max(target, int(np.prod(shape[axis + 1:])))


def test_streamed_sweep_resumes_after_an_interrupt(tmp_path):
    out = tmp_path / "sweep.nc"
    model = pendulum(samples=24)
    uninterrupted = sweep(model, OMEGA, 4, progress=False)

    def stop(done, total):
        if done >= 5:
            raise KeyboardInterrupt

    options = OutputOptions(stream=True)
    with pytest.raises(KeyboardInterrupt):
        sweep(model, OMEGA, 4, out=out, execution=CHUNKS, progress=stop, output=options)
    assert not out.exists() and len(list(out.with_name("sweep.nc.parts").glob("chunk-*.npz"))) == 1
    calls = []
    resumed = sweep(model, OMEGA, 4, out=out, execution=CHUNKS, resume=True, output=options,
                    progress=lambda d, t: calls.append(d))
    assert calls[0] == 10  # the checkpointed chunk was not recomputed
    xr.testing.assert_identical(without_attrs(resumed), without_attrs(uninterrupted))
    again = sweep(model, OMEGA, 4, out=out, resume=True, output=options, progress=lambda d, t: pytest.fail("rerun"))
    xr.testing.assert_identical(again, load(out))


def test_local_workers_write_their_chunks_and_the_file_equals_serial(tmp_path):
    """Streamed on local worker processes: the workers write their checkpoint files and send
    receipts; the file equals the serial sweep's."""
    model = pendulum(samples=24)
    serial = sweep(model, OMEGA, 4, progress=False)
    out = tmp_path / "workers.nc"
    streamed = sweep(model, OMEGA, 4, workers=2, out=out, progress=False, output=OutputOptions(stream=True),
                     execution=ExecutionOptions(chunk_size=2, eager_workers=True))
    assert streamed.attrs["backend"] == "processes"
    xr.testing.assert_identical(without_attrs(load(out)), without_attrs(serial))


def test_streamed_on_dask_equals_serial(tmp_path):
    model = pendulum(samples=24)
    serial = sweep(model, OMEGA, 4, progress=False)
    out = tmp_path / "dask.nc"
    sweep(model, OMEGA, 4, workers=2, out=out, progress=False, output=OutputOptions(stream=True),
          execution=ExecutionOptions("local", 3))
    xr.testing.assert_identical(without_attrs(load(out)), without_attrs(serial))


def test_local_workers_write_their_chunks_unstreamed_and_the_file_equals_serial(tmp_path):
    """Not streamed, on local worker processes: the workers write their chunks' checkpoint files
    and send the chunks back; the result and its file equal the serial sweep's, with failed
    points and a parameter grid; no parts are left."""
    chunks = ExecutionOptions(chunk_size=2)  # the same chunks (a failed batch's message says so)
    serial = sweep(flaky, OMEGA, 4, parameters=GRID, progress=False, execution=chunks)
    out = tmp_path / "workers.nc"
    saved = sweep(flaky, OMEGA, 4, parameters=GRID, workers=2, out=out, progress=False,
                  execution=ExecutionOptions(chunk_size=2, eager_workers=True), output=OutputOptions(stream=False))
    assert saved.attrs["backend"] == "processes" and not out.with_name(out.name + ".parts").exists()
    xr.testing.assert_identical(without_attrs(saved), without_attrs(serial))
    xr.testing.assert_identical(without_attrs(load(out)), without_attrs(serial))
