"""Speed sweeps (and speed x parameter grids): serial, on local worker processes, or on Dask.

Flow: the points of the grid (parameters..., omega) get flat indices and are split into
chunks; each chunk's speeds at one grid point are solved together by
:meth:`periodyn.analysis.SpeedSolver.solve_many` (point by point with
:func:`periodyn.analysis.solve_point` for callable models) by a backend (in this process, a local process pool, or a Dask cluster); the parent
collects finished chunks, checkpoints each into ``<out>.parts/`` (written atomically by
rename) and at the end merges them into one result file (:mod:`periodyn.results`).

Local worker processes start with one Numba/BLAS/OpenMP thread each (environment
set before they import numpy; Dask workers started by ``scheduler="local"`` too; on an
existing cluster only Numba is limited, so start its workers with those variables, see
``WORKER_THREAD_ENV``). The job (model and speeds) reaches each worker once: the model
the parent built for the first grid point travels with its omega-polynomial spectra
already computed, other grid points are built once per worker, never per speed.
Every point is computed by the same functions on the same inputs whatever the backend
(stacked LAPACK calls give each matrix the result of a single call), so serial, parallel
and distributed results agree.

A point whose solver raises :class:`~periodyn.errors.ConvergenceError` is kept as a
failed point (NaN, ``status = 1``, ``message``), never as a result.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import multiprocessing
import os
import shutil
import sys
import threading
import time
import zipfile
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping, Sequence


import cloudpickle
import numpy as np
import xarray as xr

from .analysis import SpeedBatch, SpeedSolver, check_speeds, solve_point
from .errors import ConvergenceError, InputError
from .hill import METHODS
from .progress import Progress
from .results import STATUS_FAILED, STATUS_SOLVED, load, options_attrs, package_versions, save
from .spectra import harmonic_indices
from .system import OmegaSplitModel, RheoLinear

__all__ = ["sweep", "sweep_file", "available_cores", "auto_workers", "reference_frequencies", "WORKER_THREAD_ENV",
           "AUTO_PARALLEL_POINTS"]

#: Environment of worker processes: one thread per library, set before numpy is imported.
WORKER_THREAD_ENV = {
    "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
    "VECLIB_MAXIMUM_THREADS": "1", "NUMEXPR_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1",
}
_MAX_CHUNK = 64  # points per chunk: checkpoint granularity (work lost at an interrupt) and load balance
_CHUNKS_PER_WORKER = 8


def available_cores() -> int:
    """CPU cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


#: Sweeps with fewer points run in one process under ``workers="auto"``: starting a
#: worker process (imports, first point) costs about a second.
AUTO_PARALLEL_POINTS = 2000


def auto_workers(points: int) -> int:
    """Worker processes for a sweep of ``points`` points: all cores from
    AUTO_PARALLEL_POINTS on, else 1."""
    return available_cores() if points >= AUTO_PARALLEL_POINTS else 1


# ----------------------------------------------------------------------------- models
class _ModelSource:
    """Gives the system at one grid point. ``model`` is an OmegaSplitModel or a callable
    omega -> RheoLinear; with a parameter grid it is a builder called with the grid
    point's keyword values, returning either. Built models (with their cached spectra)
    are kept and travel with the job, so workers build only grid points not built yet."""

    def __init__(self, model, grid_names: tuple[str, ...], grid_values: tuple[np.ndarray, ...],
                 samples: int | None):
        self.model = model
        self.grid_names = grid_names
        self.grid_values = grid_values
        self.samples = samples
        self._built: dict[tuple[int, ...], Any] = {}

    def parameters(self, index: tuple[int, ...]) -> dict[str, Any]:
        """Grid point ``index`` as builder keyword values."""
        return {name: _python_scalar(values[i]) for name, values, i in zip(self.grid_names, self.grid_values, index)}

    def model_at(self, index: tuple[int, ...]):
        built = self._built.get(index)
        if built is None:
            if self.grid_names:
                params = self.parameters(index)
                try:
                    built = self.model(**params)
                except InputError as exc:
                    raise InputError(f"model builder with {_describe(params)}: {exc}") from None
                except TypeError as exc:
                    raise InputError(f"model builder does not accept {_describe(params)} ({exc}); "
                                     "grid parameters must be keyword arguments of the builder") from None
            else:
                built = self.model
            if isinstance(built, OmegaSplitModel):
                if self.samples is not None:
                    built = built.with_samples(self.samples)
            elif not callable(built):
                raise InputError(f"a model must be a periodyn.OmegaSplitModel or a callable omega -> RheoLinear, "
                                 f"got {type(built).__name__}")
            self._built[index] = built
        return built

    def system(self, index: tuple[int, ...], omega: float) -> RheoLinear:
        model = self.model_at(index)
        system = model.at(omega) if isinstance(model, OmegaSplitModel) else model(omega)
        if not isinstance(system, RheoLinear):
            raise InputError(f"the model callable returned {type(system).__name__} at omega = {omega:.6g} rad/s; "
                             "it must return a periodyn.RheoLinear")
        if self.samples is not None and system.samples != self.samples:
            raise InputError(f"samples = {self.samples} was asked for but the model callable gives systems with "
                             f"{system.samples} samples; drop samples or build the systems with {self.samples}")
        return system


def _python_scalar(value):
    return value.item() if isinstance(value, np.generic) else value


def _describe(params: Mapping[str, Any]) -> str:
    return ", ".join(f"{k} = {v!r}" for k, v in params.items()) or "no parameters"


# ----------------------------------------------------------------------------- job
@dataclass
class _Job:
    """Everything a worker needs; sent once per worker. Points have flat indices
    into ``shape = (*grid, n_omega)``."""

    source: _ModelSource
    omega: np.ndarray
    harmonics: int
    stability: bool
    method: str
    n_outputs: int
    n_exponents: int
    _solvers: dict = field(default_factory=dict, repr=False)  # per grid point, built where used

    def __getstate__(self):
        state = dict(self.__dict__)
        state["_solvers"] = {}  # speed solvers are rebuilt in each worker, never shipped
        return state

    def batch(self, grid_index: tuple[int, ...], omegas: np.ndarray) -> SpeedBatch:
        """Results at one grid point for the speeds omegas: an OmegaSplitModel goes through
        its SpeedSolver (omega-polynomial blocks built once per model, chunks of speeds at
        once), a callable model point by point through solve_point."""
        model = self.source.model_at(grid_index)
        if isinstance(model, OmegaSplitModel):
            solver = self._solvers.get(grid_index)
            if solver is None:
                solver = self._solvers[grid_index] = SpeedSolver(model, self.harmonics, self.stability, self.method)
            return solver.solve_many(omegas)
        points, messages = [], []
        for w in omegas:
            try:
                points.append(solve_point(self.source.system(grid_index, w), self.harmonics,
                                          stability=self.stability, method=self.method))
                messages.append("")
            except ConvergenceError as exc:
                points.append(None)
                messages.append(str(exc) or type(exc).__name__)
            except InputError as exc:
                raise InputError(f"at omega = {w:.6g} rad/s: {exc}") from None
        return SpeedBatch.from_points(omegas, points, messages)

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.source.grid_values) + (len(self.omega),)

    def empty(self, count: int) -> dict[str, np.ndarray]:
        """Chunk arrays for ``count`` points, NaN-filled (failed until solved)."""
        h, o, e = 2 * self.harmonics + 1, self.n_outputs, self.n_exponents
        return {
            "index": np.zeros(count, dtype=np.int64),
            "amplitude": np.full((count, o), np.nan), "mean": np.full((count, o), np.nan),
            "harmonics": np.full((count, h, o), np.nan + 0j),
            "residual": np.full(count, np.nan), "max_real_exponent": np.full(count, np.nan),
            "exponents": np.full((count, e), np.nan + 0j), "multipliers": np.full((count, e), np.nan + 0j),
            "stable": np.zeros(count, dtype=bool),
            "status": np.full(count, STATUS_FAILED, dtype=np.int8),
            "message": np.full(count, "", dtype=object),
        }

    def solve(self, indices: np.ndarray) -> dict[str, np.ndarray]:
        """Solve the points with these flat indices; returns chunk arrays (see :meth:`empty`)."""
        out = self.empty(len(indices))
        out["index"][:] = indices
        located = np.unravel_index(indices, self.shape)
        with np.errstate(all="ignore"):  # overflow becomes a failed point with its reason (below)
            self._solve_into(out, located)
        out["message"] = out["message"].astype(str)
        return out

    def _solve_into(self, out: dict[str, np.ndarray], located: tuple[np.ndarray, ...]) -> None:
        indices = out["index"]
        grid = np.stack(located[:-1], axis=1) if len(located) > 1 else np.zeros((len(indices), 0), dtype=np.int64)
        for key in np.unique(grid, axis=0):
            rows = np.nonzero((grid == key).all(axis=1))[0]
            grid_index = tuple(int(k) for k in key)
            try:
                batch = self.batch(grid_index, self.omega[located[-1][rows]])
            except InputError as exc:
                if not self.source.grid_names:
                    raise
                raise InputError(f"{exc} ({_describe(self.source.parameters(grid_index))})") from None
            if (batch.output_harmonics.shape[1:] != out["harmonics"].shape[1:]
                    or batch.exponents.shape[1:] != (self.n_exponents,)):
                raise InputError(f"the model at {_describe(self.source.parameters(grid_index))} has "
                                 "other outputs or coordinates than at the first point; every grid point must have "
                                 "the same outputs and coordinates")
            solved = batch.message == ""
            nonfinite = _nonfinite(batch, self.stability)
            nonfinite[~solved] = ""  # a failed point keeps the reason it failed
            out["message"][rows] = np.where(nonfinite != "", nonfinite, batch.message)
            solved &= nonfinite == ""
            for name, column in (("amplitude", batch.amplitude), ("mean", batch.mean),
                                 ("harmonics", batch.output_harmonics), ("residual", batch.residual),
                                 ("max_real_exponent", batch.max_real), ("exponents", batch.exponents),
                                 ("multipliers", batch.multipliers), ("stable", batch.stable)):
                out[name][rows[solved]] = column[solved]
            out["status"][rows[solved]] = STATUS_SOLVED


_CHECKED = ("amplitude", "mean", "output_harmonics", "residual")
_CHECKED_STABILITY = ("exponents", "multipliers", "max_real")


def _nonfinite(batch: SpeedBatch, stability: bool) -> np.ndarray:
    """Per speed of ``batch``: '' where every number of the result is finite, else the
    reason naming the quantities that are not (the point is then a failed point)."""
    names = _CHECKED + (_CHECKED_STABILITY if stability else ())
    bad = {name: ~np.isfinite(getattr(batch, name)).reshape(len(batch), -1).any(axis=1) for name in names}
    reasons = np.full(len(batch), "", dtype=object)
    for i in np.flatnonzero(np.any(list(bad.values()), axis=0)):
        which = ", ".join(name for name in names if bad[name][i])
        reasons[i] = (f"non-finite result ({which}) at omega = {batch.omega[i]:.6g} rad/s: the model's "
                      "coefficients or the solution overflow; check the model parameters (sizes, units)")
    return reasons


# ----------------------------------------------------------------------------- backends
_WORKER_JOB: _Job | None = None
_DASK_JOBS: dict[str, _Job] = {}


def _limit_threads() -> None:
    """One BLAS/OpenMP and one Numba thread in this (worker) process from now on."""
    import numba
    from threadpoolctl import threadpool_limits

    threadpool_limits(1)
    numba.set_num_threads(1)


@contextlib.contextmanager
def _one_thread() -> Iterator[None]:
    """One BLAS/OpenMP and one Numba thread inside the block, as in the workers, so the
    serial sweep computes every point exactly as a worker process does."""
    import numba
    from threadpoolctl import threadpool_limits

    numba_threads = numba.get_num_threads()
    with threadpool_limits(1):
        numba.set_num_threads(1)
        try:
            yield
        finally:
            numba.set_num_threads(numba_threads)


def _exit_with_parent() -> None:
    """End this worker when the sweep process dies (even by SIGKILL): a killed parent
    cannot shut the pool down, and its task queue never reports end-of-file."""
    parent = multiprocessing.parent_process()

    def watch():
        parent.join()
        os._exit(1)

    threading.Thread(target=watch, name="periodyn-parent-watch", daemon=True).start()


def _init_worker(payload: bytes) -> None:
    global _WORKER_JOB
    _exit_with_parent()
    _limit_threads()
    _WORKER_JOB = cloudpickle.loads(payload)


def _solve_in_worker(indices: np.ndarray) -> dict[str, np.ndarray]:
    return _WORKER_JOB.solve(indices)


def _solve_on_dask_worker(payload: bytes, token: str, indices: np.ndarray) -> dict[str, np.ndarray]:
    job = _DASK_JOBS.get(token)
    if job is None:
        _limit_threads()
        job = _DASK_JOBS.setdefault(token, cloudpickle.loads(payload))
    return job.solve(indices)


@contextlib.contextmanager
def _worker_environment() -> Iterator[None]:
    """Start processes inside the block with the one-thread environment and without
    re-running the caller's script: the job reaches workers by cloudpickle, so a script
    lacking an ``if __name__ == "__main__"`` guard must not be executed again in them
    (with spawn and forkserver, multiprocessing re-imports ``__main__`` from its
    ``__file__`` in every child)."""
    saved = {k: os.environ.get(k) for k in WORKER_THREAD_ENV}
    os.environ.update(WORKER_THREAD_ENV)
    main = sys.modules["__main__"]
    main_file = main.__dict__.pop("__file__", None) if getattr(main, "__spec__", None) is None else None
    try:
        yield
    finally:
        if main_file is not None:
            main.__file__ = main_file
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _run_serial(job: _Job, chunks: list[np.ndarray], workers: int, scheduler) -> Iterator[dict]:
    for chunk in chunks:
        with _one_thread():
            result = job.solve(chunk)
        yield result


def _process_context():
    """Start method for local workers: "forkserver" where available (a server process
    imports periodyn and loads the speed solver's compiled kernels once, in the
    one-thread environment of its first start, and forks the workers, so pools after the
    first start in milliseconds), else "spawn"."""
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload([__name__, "periodyn._forkserver_preload"])
    return context


def _run_processes(job: _Job, chunks: list[np.ndarray], workers: int, scheduler) -> Iterator[dict]:
    payload = cloudpickle.dumps(job)
    with _worker_environment():
        pool = ProcessPoolExecutor(max_workers=workers, mp_context=_process_context(),
                                   initializer=_init_worker, initargs=(payload,))
        try:
            futures = [pool.submit(_solve_in_worker, chunk) for chunk in chunks]
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise
    try:
        for future in as_completed(futures):
            yield future.result()
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _dask_client(scheduler, workers: int):
    """(client, things to close): an existing Client, 'local' (a LocalCluster with
    ``workers`` one-thread processes) or a scheduler address."""
    import dask
    from distributed import Client, LocalCluster

    if isinstance(scheduler, Client):
        return scheduler, []
    if scheduler == "local":
        with dask.config.set({"distributed.nanny.pre-spawn-environ": WORKER_THREAD_ENV}):
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
        client = Client(cluster)
        return client, [client, cluster]
    try:
        client = Client(scheduler, timeout="10s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"cannot connect to the Dask scheduler at {scheduler!r} ({exc}); check the address "
                         "(tcp://host:8786) and that the scheduler is running") from None
    return client, [client]


def _run_dask(job: _Job, chunks: list[np.ndarray], workers: int, scheduler) -> Iterator[dict]:
    from distributed import as_completed as dask_as_completed

    client, owned = _dask_client(scheduler, workers)
    futures = []
    try:
        payload = cloudpickle.dumps(job)
        token = hashlib.sha256(payload).hexdigest()
        shared = client.scatter(payload, broadcast=True)
        futures = [client.submit(_solve_on_dask_worker, shared, token, chunk, pure=False) for chunk in chunks]
        for future in dask_as_completed(futures):
            yield future.result()
    finally:
        if futures:
            client.cancel(futures)
        for thing in owned:
            thing.close()


# ----------------------------------------------------------------------------- checkpoints
class _Checkpoint:
    """Finished chunks of the sweep writing ``out``, kept in ``<out>.parts/`` until merged.

    Each chunk is an .npz file written under a temporary name and renamed, so a killed
    process leaves either a whole chunk or none; ``manifest.json`` holds the fingerprint
    of the sweep settings so a resume refuses parts of a different sweep.
    """

    def __init__(self, out: Path, fingerprint: str, resume: bool):
        self.out = out
        self.parts = out.with_name(out.name + ".parts")
        self.fingerprint = fingerprint
        self.manifest = self.parts / "manifest.json"
        if self.manifest.exists():  # written before the first chunk: without it, nothing was kept
            if not resume:
                raise InputError(f"{self.parts} holds an interrupted sweep; resume it with --resume "
                                 "(resume=True) or delete that directory to start over")
            try:
                stored = json.loads(self.manifest.read_text())["fingerprint"]
            except (OSError, ValueError, KeyError):
                stored = None
            if stored != fingerprint:
                raise InputError(f"{self.parts} belongs to a sweep with other settings (model, speeds, harmonics, "
                                 "samples, stability or method); rerun with the original settings, or delete "
                                 "that directory to start over")
        if self.parts.exists():
            for stale in self.parts.glob(".tmp-*"):
                stale.unlink(missing_ok=True)

    def _atomic_write(self, path: Path, write: Callable) -> None:
        tmp = self.parts / f".tmp-{os.getpid()}-{path.name}"
        try:
            with open(tmp, "wb") as f:
                write(f)
            os.replace(tmp, path)
        except BaseException:
            tmp.unlink(missing_ok=True)
            raise

    def chunks(self) -> Iterator[dict[str, np.ndarray]]:
        """Chunks already finished (unreadable files are dropped and recomputed)."""
        if not self.parts.exists():
            return
        for path in sorted(self.parts.glob("chunk-*.npz")):
            try:
                with np.load(path, allow_pickle=False) as data:
                    chunk = {k: data[k] for k in data.files}
            except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile):
                path.unlink(missing_ok=True)
                continue
            yield chunk

    def write(self, chunk: dict[str, np.ndarray]) -> None:
        """Store one finished chunk (the folder and its manifest are made with the first)."""
        if not self.manifest.exists():
            self.parts.mkdir(parents=True, exist_ok=True)
            self._atomic_write(self.manifest, lambda f: f.write(json.dumps({"fingerprint": self.fingerprint}).encode()))
        name = f"chunk-{int(chunk['index'][0]):010d}-{len(chunk['index'])}.npz"
        self._atomic_write(self.parts / name, lambda f: np.savez(f, **chunk))

    def finish(self, ds: xr.Dataset) -> None:
        """Write the merged result file, then drop the parts."""
        save(ds, self.out)
        shutil.rmtree(self.parts, ignore_errors=True)


# ----------------------------------------------------------------------------- driver
@dataclass
class _Collected:
    """Full-size result arrays over flat point indices, filled chunk by chunk."""

    arrays: dict[str, np.ndarray]
    done: np.ndarray = field(init=False)

    def __post_init__(self):
        self.done = np.zeros(len(self.arrays["index"]), dtype=bool)

    def add(self, chunk: dict[str, np.ndarray]) -> None:
        idx = chunk["index"]
        for key, values in chunk.items():
            if key != "index":
                self.arrays[key][idx] = values
        self.done[idx] = True


def _check_grid(model, parameters) -> tuple[tuple[str, ...], tuple[np.ndarray, ...]]:
    if not parameters:
        return (), ()
    if isinstance(model, OmegaSplitModel) or not callable(model):
        raise InputError("a parameter grid needs a model builder: pass a callable (e.g. periodyn.examples.pendulum) "
                         "that takes the grid parameters as keyword arguments")
    names, values = [], []
    for name, vals in parameters.items():
        arr = np.atleast_1d(np.asarray(vals))
        if arr.ndim != 1 or arr.size == 0:
            raise InputError(f"parameter grid '{name}' must be a non-empty 1-D list of values, got shape {arr.shape}")
        if name == "omega":
            raise InputError("omega is the sweep axis; give it as the omega argument, not in parameters")
        names.append(str(name))
        values.append(arr)
    return tuple(names), tuple(values)


def _check_int(name: str, value, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def _model_identity(model) -> str:
    if isinstance(model, OmegaSplitModel):
        digest = hashlib.sha256()
        for a in (model.mass, model.damping, model.stiffness, model.force, model.output_maps):
            digest.update(np.ascontiguousarray(a).tobytes())
        digest.update(repr((model.name, model.output_names, model.coordinate_names)).encode())
        return digest.hexdigest()
    return f"{getattr(model, '__module__', '')}.{getattr(model, '__qualname__', type(model).__qualname__)}"


def _fingerprint(job: _Job, options: dict, identity: str) -> str:
    digest = hashlib.sha256(json.dumps(options, sort_keys=True).encode())
    digest.update(identity.encode())
    digest.update(job.omega.tobytes())
    for name, values in zip(job.source.grid_names, job.source.grid_values):
        digest.update(name.encode())
        digest.update(np.asarray(values).tobytes())
    return digest.hexdigest()


def _split(indices: np.ndarray, chunk_size: int) -> list[np.ndarray]:
    return [indices[i:i + chunk_size] for i in range(0, len(indices), chunk_size)]


def reference_frequencies(model) -> dict[str, float]:
    """Reference frequencies (rad/s) of a model: its ``metadata`` entries named omega*."""
    meta = getattr(model, "metadata", None)
    if not isinstance(meta, Mapping):
        return {}
    return {str(k): float(v) for k, v in meta.items()
            if str(k).startswith("omega") and isinstance(v, (int, float, np.number)) and not isinstance(v, bool)}


def _dataset(job: _Job, collected: _Collected, probe: RheoLinear, reference: tuple[str, float] | None,
             attrs: dict) -> xr.Dataset:
    shape = job.shape
    grid = job.source.grid_names
    base = grid + ("omega",)
    a = {k: v.reshape(shape + v.shape[1:]) for k, v in collected.arrays.items() if k != "index"}
    coords = {"omega": ("omega", job.omega, {"units": "rad/s", "long_name": "driving speed"}),
              "harmonic": ("harmonic", harmonic_indices(job.harmonics),
                           {"long_name": "harmonic index l of exp(i l omega t)", "units": "1"}),
              "output": ("output", np.array(probe.output_names, dtype=str)),
              "exponent": ("exponent", np.arange(job.n_exponents), {"long_name": "characteristic exponent index"})}
    for name, values in zip(grid, job.source.grid_values):
        coords[name] = (name, values, {"long_name": f"model parameter {name}"})
    if reference is not None:
        ref_name, ref_value = reference
        coords[f"omega_over_{ref_name}"] = ("omega", job.omega / ref_value,
                                            {"units": "1", "long_name": f"omega / {ref_name}",
                                             "reference_frequency": ref_value})
    out_units = "units of each output (model-defined)"
    variables = {
        "amplitude": (base + ("output",), a["amplitude"],
                      {"long_name": "half peak-to-peak amplitude", "units": out_units}),
        "mean": (base + ("output",), a["mean"], {"long_name": "mean over one period", "units": out_units}),
        "harmonics": (base + ("harmonic", "output"), a["harmonics"],
                      {"long_name": "Fourier coefficients y_l of the outputs, y(t) = sum_l y_l exp(i l omega t)",
                       "units": out_units}),
        "residual": (base, a["residual"], {"long_name": "harmonic-balance residual norm", "units": "1"}),
        "exponents": (base + ("exponent",), a["exponents"],
                      {"long_name": "characteristic exponents (NaN without stability)", "units": "rad/s"}),
        "multipliers": (base + ("exponent",), a["multipliers"], {"long_name": "Floquet multipliers", "units": "1"}),
        "max_real_exponent": (base, a["max_real_exponent"],
                              {"long_name": "largest real part of the characteristic exponents", "units": "1/s"}),
        "stable": (base, a["stable"], {"long_name": "periodic solution asymptotically stable"}),
        "status": (base, a["status"], {"long_name": "0 solved, 1 failed (see message)",
                                       "flag_values": np.array([STATUS_SOLVED, STATUS_FAILED], dtype=np.int8),
                                       "flag_meanings": "solved failed"}),
        "message": (base, a["message"].astype(str), {"long_name": "why the point failed, empty if solved"}),
    }
    return xr.Dataset(variables, coords=coords, attrs=attrs)


_BACKENDS = {"serial": _run_serial, "processes": _run_processes, "dask": _run_dask}


def sweep(model, omega, harmonics: int, samples: int | None = None, stability: bool = True, method: str = "auto", *,
          parameters: Mapping[str, Sequence] | None = None, workers: int = 1, scheduler=None, out=None,
          resume: bool = False, progress: bool | None | Callable[[int, int], None] = None,
          chunk_size: int | None = None, reference: tuple[str, float] | None = None, name: str | None = None,
          sweep_file_text: str | None = None) -> xr.Dataset:
    """Periodic solution and stability at every speed (and parameter grid point).

    model: a :class:`periodyn.OmegaSplitModel`, a callable omega (rad/s) -> RheoLinear, or,
        with ``parameters``, a builder called as ``model(**point)`` returning either.
    omega: speeds (k,), rad/s, > 0. harmonics: m. samples: p (resamples an OmegaSplitModel;
        None keeps the model's). stability/method: passed to ``solve_point``.
    parameters: grid ``{name: values}``; the result gets one dimension per name, in order.
    workers: processes (1 = in this process, 0 = all cores). scheduler: Dask ``Client``,
        scheduler address, or ``"local"`` (a LocalCluster of ``workers`` processes).
    out: result file; chunks are checkpointed in ``<out>.parts/`` and ``resume=True``
        continues an interrupted sweep, recomputing only missing points.
    progress: None (bar on a terminal, lines otherwise, after 1 s), False, True, or a
        callable (done, total). reference: (name, rad/s) adds coordinate omega_over_<name>;
        by default the model's first metadata entry named omega* is used.

    Returns the dataset described in :mod:`periodyn.results` (also written to ``out``).
    """
    started = time.perf_counter()
    w = check_speeds(omega)
    m = _check_int("harmonics", harmonics, 1)
    p = None if samples is None else _check_int("samples", samples, 1)
    if method not in METHODS:
        raise InputError(f"unknown method {method!r}; choose one of {METHODS}")
    workers = _check_int("workers", workers, 0) or available_cores()
    if resume and out is None:
        raise InputError("resume=True needs out=<result file>: the checkpoints live in <out>.parts/")
    grid_names, grid_values = _check_grid(model, parameters)
    source = _ModelSource(model, grid_names, grid_values, p)
    first = (0,) * len(grid_names)
    with np.errstate(all="ignore"):  # an overflowing model gives failed points, reported per point
        probe = source.system(first, float(w[0]))
    if reference is None:
        refs = reference_frequencies(source.model_at(first))
        reference = next(iter(refs.items()), None)
    job = _Job(source, w, m, bool(stability), method, len(probe.output_names), 2 * probe.n)
    model_name = name or getattr(source.model_at(first), "name", None) or getattr(model, "__name__", "model")
    options = {"model": model_name, "harmonics": m, "samples": probe.samples, "stability": bool(stability),
               "method": method, "parameters": list(grid_names)}
    total = int(np.prod(job.shape))
    backend = "dask" if scheduler is not None else "processes" if workers > 1 else "serial"

    checkpoint = None
    collected = _Collected(job.empty(total))
    collected.arrays["index"][:] = np.arange(total)
    if out is not None:
        out = Path(out)
        fingerprint = _fingerprint(job, options, sweep_file_text or _model_identity(model))
        parts = out.with_name(out.name + ".parts")
        if resume and out.is_file() and not parts.exists():
            finished = load(out)
            if finished.attrs.get("fingerprint") != fingerprint:
                raise InputError(f"{out} is a finished result made with other settings (model, speeds, harmonics, "
                                 "samples, stability or method), and resuming would overwrite it; rerun with "
                                 "the settings it was made with, give another --out (out=) file, or drop "
                                 "--resume (resume=False) to replace it")
            return finished
        checkpoint = _Checkpoint(out, fingerprint, resume)
        for chunk in checkpoint.chunks():
            collected.add(chunk)
    pending = np.flatnonzero(~collected.done)
    size = chunk_size or max(1, min(_MAX_CHUNK, math.ceil(len(pending) / (_CHUNKS_PER_WORKER * workers))))
    chunks = _split(pending, _check_int("chunk_size", size, 1))

    with Progress(total, total - len(pending), f"sweep {model_name}", progress) as bar:
        for chunk in _BACKENDS[backend](job, chunks, workers, scheduler):
            collected.add(chunk)
            if checkpoint is not None:
                checkpoint.write(chunk)
            bar.update(len(chunk["index"]))

    attrs = {"title": f"periodyn sweep of {model_name}", "created_by": "periodyn.sweep",
             **options_attrs(options), "backend": backend, "workers": workers if backend != "serial" else 1,
             "points": total, "failed_points": int((collected.arrays["status"] != STATUS_SOLVED).sum()),
             "elapsed_s": time.perf_counter() - started,
             "package_versions": json.dumps(package_versions(), sort_keys=True),
             "sweep_file_text": sweep_file_text or ""}
    if checkpoint is not None:
        attrs["fingerprint"] = checkpoint.fingerprint
    ds = _dataset(job, collected, probe, reference, attrs)
    if checkpoint is not None:
        checkpoint.finish(ds)
    return ds


def sweep_file(spec, *, omega=None, out=None, workers: int | str = 1, scheduler=None, resume: bool = False,
               progress=None, chunk_size: int | None = None) -> xr.Dataset:
    """Run a validated sweep file (:class:`periodyn.config.SweepSpec`); ``omega``
    (start, stop, num) in the file's unit replaces its speeds; ``workers="auto"``:
    see :func:`auto_workers`."""
    if workers == "auto":
        workers = auto_workers(spec.points(omega))
    plan = spec.plan(omega)
    return sweep(plan.model, plan.omega, spec.harmonics, spec.samples, spec.stability, spec.method,
                 parameters=plan.parameters, workers=workers, scheduler=scheduler, out=out, resume=resume,
                 progress=progress, chunk_size=chunk_size, reference=plan.reference, name=spec.example,
                 sweep_file_text=spec.text)
