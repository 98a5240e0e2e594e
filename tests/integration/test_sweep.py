"""periodyn.sweep: results per point, failed points, parameter grids, backends, checkpoints."""

from __future__ import annotations

import time
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

from periodyn.speeds import SpeedSolver, solve_point
from periodyn.errors import ConvergenceError, InputError
from periodyn.examples import pendulum
from periodyn.results import STATUS_FAILED, STATUS_SOLVED, load
from periodyn.engine.front import ExecutionOptions, sweep
from tests.integration.datasets import without_attrs

W0 = np.sqrt(9.81)
OMEGA = W0 * np.linspace(0.1, 1.4, 24)
M = 6


@pytest.fixture(scope="module")
def model():
    return pendulum(samples=32)


@pytest.fixture(scope="module")
def serial(model):
    return sweep(model, OMEGA, M, progress=False)


def test_every_point_matches_the_speed_solver_and_solve_point(model, serial):
    solver = SpeedSolver(model, M)
    for k in (0, 11, 23):
        point = solver.solve(OMEGA[k])
        sel = serial.isel(omega=k)
        np.testing.assert_array_equal(sel["harmonics"].values, point.output_harmonics)
        np.testing.assert_array_equal(sel["amplitude"].values, point.amplitude)
        np.testing.assert_array_equal(sel["exponents"].values, point.exponents)
        assert float(sel["max_real_exponent"]) == point.max_real
        assert bool(sel["stable"]) == point.stable
        direct = solve_point(model.at(OMEGA[k]), M)  # the per-speed path, to round-off
        np.testing.assert_allclose(sel["harmonics"].values, direct.output_harmonics,
                                   atol=1e-13 * np.abs(direct.output_harmonics).max())
        np.testing.assert_allclose(float(sel["max_real_exponent"]), direct.max_real, rtol=1e-12)


def test_dataset_layout_and_units(serial):
    assert serial["amplitude"].dims == ("omega", "output")
    assert serial["harmonics"].dims == ("omega", "harmonic", "output")
    assert serial["exponents"].dims == ("omega", "exponent")
    assert list(serial["harmonic"].values) == list(range(-M, M + 1))
    assert list(serial["output"].values) == ["phi"]
    assert serial["omega"].attrs["units"] == "rad/s"
    assert serial["max_real_exponent"].attrs["units"] == "1/s"
    np.testing.assert_allclose(serial["omega_over_omega0"].values, OMEGA / W0, rtol=1e-12)
    assert (serial["status"].values == STATUS_SOLVED).all()
    assert serial.attrs["harmonics"] == M and serial.attrs["samples"] == 32
    assert "numpy" in serial.attrs["package_versions"]
    # the paper's resonance near omega0/2 and the instability near omega0 are in the data
    unstable = serial["omega_over_omega0"].values[~serial["stable"].values]
    assert unstable.min() > 0.85 and unstable.size > 0


def test_convergence_failures_are_recorded_not_returned(model):
    def flaky(omega):
        if 2.0 < omega < 2.5:
            raise ConvergenceError(f"Newton did not converge at {omega:.3f}", residual=1.0, iterations=50)
        return model.at(omega)

    ds = sweep(flaky, OMEGA, M, progress=False)
    bad = (OMEGA > 2.0) & (OMEGA < 2.5)
    assert bad.any()
    assert (ds["status"].values[bad] == STATUS_FAILED).all()
    assert np.isnan(ds["amplitude"].values[bad]).all() and np.isnan(ds["max_real_exponent"].values[bad]).all()
    assert not ds["stable"].values[bad].any()
    assert all("Newton did not converge" in m for m in ds["message"].values[bad])
    assert ds.attrs["failed_points"] == bad.sum()
    assert (ds["message"].values[~bad] == "").all()


def test_samples_resample_an_omega_split_model(model):
    ds = sweep(model, OMEGA[:3], M, samples=40, stability=False, progress=False)
    point = SpeedSolver(pendulum(samples=40), M, stability=False).solve(OMEGA[1])
    np.testing.assert_array_equal(ds["harmonics"].values[1], point.output_harmonics)
    assert np.isnan(ds["exponents"].values).all()
    assert ds.attrs["samples"] == 40 and ds.attrs["stability"] == 0


def test_parameter_grid_over_builder_keywords():
    zetas = [0.005, 0.02]
    ds = sweep(pendulum, OMEGA[:5], M, samples=32, parameters={"zeta": zetas}, progress=False)
    assert ds["amplitude"].dims == ("zeta", "omega", "output")
    np.testing.assert_array_equal(ds["zeta"].values, zetas)
    for i, z in enumerate(zetas):
        point = solve_point(pendulum(zeta=z, samples=32).at(OMEGA[3]), M)  # the per-speed path, to round-off
        np.testing.assert_allclose(ds["amplitude"].values[i, 3], point.amplitude, rtol=1e-12)
    # the damping moment -2 zeta w0 w drives the mean: four times zeta, larger mean deflection
    assert (np.abs(ds["mean"].values[1]) > 3 * np.abs(ds["mean"].values[0])).all()


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"omega": [0.0, 1.0]}, "positive finite speed"),
        ({"omega": [[1.0, 2.0]]}, "1-D"),
        ({"harmonics": -1}, "harmonics must be an integer >= 1"),
        ({"samples": 0}, "samples must be an integer >= 1"),
        ({"stability": "fast"}, "unknown method 'fast'"),
        ({"workers": -2}, "workers must be an integer >= 0"),
        ({"parameters": {"zeta": [0.1]}}, "parameter grid needs a model builder"),
        ({"resume": True}, "resume=True needs out="),
    ],
)
def test_bad_arguments_name_the_problem(model, kwargs, message):
    args = {"model": model, "omega": OMEGA[:2], "harmonics": M, **kwargs}
    with pytest.raises(InputError, match=message):
        sweep(progress=False, **args)


def test_builder_and_model_errors_become_input_errors():
    with pytest.raises(InputError, match="zeta"):
        sweep(pendulum, OMEGA[:2], M, parameters={"zeta": [-1.0]}, progress=False)
    with pytest.raises(InputError, match="does not accept"):
        sweep(pendulum, OMEGA[:2], M, parameters={"dampin": [0.1]}, progress=False)
    with pytest.raises(InputError, match="must return a periodyn.RheoLinear"):
        sweep(lambda w: np.eye(2), OMEGA[:2], M, progress=False)


def test_parallel_processes_identical_to_serial():
    """A grid: the first point's model travels built (lambdas included, by cloudpickle),
    the second is built by the builder inside the workers."""
    grid = {"zeta": [0.01, 0.03]}
    serial = sweep(pendulum, OMEGA, M, samples=32, parameters=grid, progress=False)
    parallel = sweep(pendulum, OMEGA, M, samples=32, parameters=grid, workers=2,
                     execution=ExecutionOptions(chunk_size=5, eager_workers=True), progress=False)
    xr.testing.assert_identical(without_attrs(parallel), without_attrs(serial))
    assert parallel.attrs["backend"] == "processes" and parallel.attrs["workers"] == 2


def test_worker_start_rule_uses_the_measured_start(model, monkeypatch):
    """Workers start only when they would take more work than their start costs; a pool after
    the first replaces the prior START_COST["later"] by its measured start (a positive time,
    not the prior), which the next decision uses."""
    from periodyn.engine import backends

    served = ExecutionOptions(worker_start="forkserver")  # the rule of workers from the fork server
    monkeypatch.setattr(backends, "START_COST", {"first": 2.0, "later": -1.0, "fork": 0.05})
    monkeypatch.setattr(backends, "_STARTED", [True])
    assert backends._worth_starting(0.1, 0.01, 2, served)   # 0.1 s left, up at once (the -1 s prior)
    backends.START_COST["later"] = 0.2
    assert not backends._worth_starting(0.1, 0.01, 2, served)  # 0.1 s left: done before a worker is up
    assert backends._worth_starting(1.0, 0.01, 2, served)      # 1 s left: 0.4 s saved
    # 0.08 s left once they are up: 0.04 s saved with one more process, 0.06 s with three,
    # against a 0.05 s wait for the last chunk
    backends.START_COST["later"] = 0.22
    assert backends._worth_starting(0.3, 0.1, 4, served) and not backends._worth_starting(0.3, 0.1, 2, served)
    backends._record_start(SimpleNamespace(ready_after=0.3, created=0.0), 0.05)
    assert backends.START_COST["later"] == pytest.approx(0.35)  # up after 0.3 s, shut down in 0.05 s
    never_up = SimpleNamespace(ready_after=None, created=time.perf_counter() - 1.0)
    backends._record_start(never_up, 0.0)  # closed before a worker was up: at least 1 s
    assert backends.START_COST["later"] >= 1.0
    sweep(model, OMEGA, M, workers=2, execution=ExecutionOptions(chunk_size=4, eager_workers=True, worker_start="forkserver"),
          progress=False)
    measured = backends.START_COST["later"]  # a measurement, or the 1 s lower bound if no worker came up
    assert np.isfinite(measured) and measured > 0.0


def test_first_start_counts_the_time_the_fork_server_already_had(monkeypatch):
    """Started ahead of the first pool, the fork server's warm-up overlaps the first
    chunks: the expected start is the prior less the time since, at least "later"."""
    from periodyn.engine import backends

    served = ExecutionOptions(worker_start="forkserver")
    monkeypatch.setattr(backends, "START_COST", {"first": 2.0, "later": 0.2, "fork": 0.05})
    monkeypatch.setattr(backends, "_STARTED", [])
    monkeypatch.setattr(backends, "_SERVER_SINCE", [])
    assert backends._start_cost(served) == 2.0
    backends._SERVER_SINCE.append(time.perf_counter() - 1.5)
    assert backends._start_cost(served) == pytest.approx(0.5, abs=0.05)
    backends._SERVER_SINCE[0] -= 5.0
    assert backends._start_cost(served) == 0.2
    backends._STARTED.append(True)
    backends._SERVER_SINCE.clear()
    assert backends._start_cost(served) == 0.2


def test_an_unused_early_fork_server_is_stopped_at_exit(monkeypatch):
    """A fork server started ahead of a pool that never came is stopped at exit (it holds
    the caller's output pipes until its warm-up ends); one a pool used is left alone."""
    import signal
    import subprocess

    from periodyn.engine import backends

    for started, stopped in (([True], False), ([], True)):
        monkeypatch.setattr(backends, "_STARTED", started)
        server = subprocess.Popen(["sleep", "30"])
        backends._stop_unused_server(server.pid)
        try:
            assert (server.wait(timeout=10) == -signal.SIGTERM) if stopped else server.poll() is None
        finally:
            server.kill()
            server.wait()


def test_chunks_of_equal_estimated_cost():
    """With costs, a chunk ends once its cost reaches the target (or at the count limit):
    slow points go in short chunks; every index once, in order."""
    from periodyn.engine.checkpoint import split

    indices = np.arange(10, 30)
    costs = np.where(indices < 14, 10.0, 1.0)  # four slow points, then fast ones
    chunks = split(indices, 8, costs, chunk_cost=10.0)
    np.testing.assert_array_equal(np.concatenate(chunks), indices)
    assert [len(c) for c in chunks] == [1, 1, 1, 1, 8, 8]  # cost 10 each, then the count limit
    assert [len(c) for c in split(indices, 8)] == [8, 8, 4]  # without costs: by count


def test_speed_costs_follow_the_stability_work(model):
    """The load-balance estimate: "auto" (Magnus ladder) costs more at low speeds, whose
    first rungs need more steps (the measured time grows alike); a fixed-step method costs
    the same at every speed."""
    w = W0 * np.array([0.002, 0.02, 0.2, 1.0])
    auto = SpeedSolver(model, M).speed_costs(w)
    assert np.all(np.diff(auto) <= 0) and auto[0] > 3 * auto[-1]
    fixed = SpeedSolver(model, M, stability="magnus").speed_costs(w)
    assert np.all(fixed == fixed[0]) and fixed[0] > 0


def test_speed_costs_of_many_speeds_are_interpolated(model):
    """Beyond COST_SPEEDS speeds the estimate is interpolated between COST_SPEEDS evenly
    spread speeds (its cost in the sweep's own process stays bounded): it is the
    interpolant of the estimate at those speeds, and its total is within 5 % of the
    speed-by-speed one."""
    from periodyn.speeds import COST_SPEEDS

    solver = SpeedSolver(model, M)
    w = W0 * np.linspace(0.01, 1.0, 4 * COST_SPEEDS + 1)
    many = solver.speed_costs(w)
    exact = np.concatenate([solver.speed_costs(part) for part in np.array_split(w, 8)])  # each <= COST_SPEEDS
    grid = np.linspace(w[0], w[-1], COST_SPEEDS)
    np.testing.assert_allclose(many, np.interp(w, grid, solver.speed_costs(grid)), rtol=1e-12)
    assert abs(many.sum() / exact.sum() - 1) < 0.05


def test_checkpoint_resume_after_interrupt(model, serial, tmp_path):
    out = tmp_path / "sweep.nc"

    def stop_after_two_chunks(done, total):
        if done >= 10:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sweep(model, OMEGA, M, out=out, execution=ExecutionOptions(chunk_size=5), progress=stop_after_two_chunks)
    parts = out.with_name("sweep.nc.parts")
    assert len(list(parts.glob("chunk-*.npz"))) == 2 and not out.exists()

    with pytest.raises(InputError, match="--resume"):
        sweep(model, OMEGA, M, out=out, execution=ExecutionOptions(chunk_size=5, eager_workers=True), progress=False)
    with pytest.raises(InputError, match="other settings"):
        sweep(model, OMEGA, M + 1, out=out, execution=ExecutionOptions(chunk_size=5), resume=True, progress=False)

    (parts / ".tmp-123-chunk-0000000010-5.npz").write_bytes(b"half a chunk")  # a killed write
    calls = []
    resumed = sweep(model, OMEGA, M, out=out, execution=ExecutionOptions(chunk_size=5), resume=True,
                    progress=lambda d, t: calls.append(d))
    assert calls[0] == 15  # started from the 10 checkpointed points
    assert not parts.exists()
    xr.testing.assert_identical(without_attrs(resumed), without_attrs(serial))
    xr.testing.assert_identical(without_attrs(load(out)), without_attrs(serial))
    # resuming a finished sweep only reads it back
    again = sweep(model, OMEGA, M, out=out, resume=True, progress=lambda d, t: pytest.fail("recomputed"))
    xr.testing.assert_identical(again, load(out))


def test_failure_before_the_first_chunk_leaves_nothing_to_resume(model, serial, tmp_path):
    out = tmp_path / "s.nc"
    with pytest.raises(InputError):
        sweep(model, OMEGA, M, out=out, execution=ExecutionOptions("tcp://127.0.0.1:1:bad"), progress=False)
    assert not out.with_name("s.nc.parts").exists()
    out.with_name("s.nc.parts").mkdir()  # killed between creating the folder and its manifest
    ds = sweep(model, OMEGA, M, out=out, progress=False)
    xr.testing.assert_identical(without_attrs(ds), without_attrs(serial))


def test_unreadable_chunk_is_recomputed(model, serial, tmp_path):
    out = tmp_path / "s.nc"

    def stop(done, total):
        if done >= 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sweep(model, OMEGA, M, out=out, execution=ExecutionOptions(chunk_size=5), progress=stop)
    (chunk,) = out.with_name("s.nc.parts").glob("chunk-*.npz")
    chunk.write_bytes(chunk.read_bytes()[:100])
    resumed = sweep(model, OMEGA, M, out=out, execution=ExecutionOptions(chunk_size=5), resume=True, progress=False)
    xr.testing.assert_identical(without_attrs(resumed), without_attrs(serial))

