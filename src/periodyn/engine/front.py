"""Speed sweeps (and speed x parameter grids): the front of :mod:`periodyn.engine`.

Flow: the points of the grid (parameters..., omega) get flat indices and are split into
chunks; a :class:`~periodyn.engine.job.Job` solves each chunk (the speeds at one grid
point together by :meth:`periodyn.speeds.SpeedSolver.solve_many`, point by point with
:func:`periodyn.speeds.solve_point` for callable models) on a backend
(:mod:`periodyn.engine.backends`: this process, local worker processes, or Dask); the
chunks are checkpointed into ``<out>.parts/`` (:mod:`periodyn.engine.checkpoint`; by
local worker processes themselves, where they are solved) and one result file laid out
by :func:`periodyn.results.to_dataset` is written at the end.

Every path runs one BLAS/Numba thread per process (:mod:`periodyn.engine.threads`), so
serial, parallel and distributed results are bit-identical. A point whose solver fails,
or whose result holds a non-finite number, is a failed point (NaN, ``status = 1``,
``message``), never a result.
"""

from __future__ import annotations

import contextlib
import json
import math
import sys
import time
from pathlib import Path
from typing import Callable, Mapping, Sequence

import numpy as np
import xarray as xr

from ..speeds import check_speeds
from .backends import BACKENDS, start_server_early
from .checkpoint import Checkpoint, Collected, fingerprint, model_identity, split
from .job import Job, ModelSource, reference_frequencies
from .options import ExecutionOptions, OutputOptions, check_int
from .threads import AUTO_PARALLEL_POINTS, WORKER_THREAD_ENV, available_cores, auto_workers
from .warmup import COMPILE_NOTE, announce_compiles, compile_ahead, kernels_cached
from ..errors import InputError
from ..stability.methods import method_named, stability_choice
from .progress import Progress
from .session import check_interrupt, sweep_guard
from .stream import STREAM_POINTS, Tally, streamed_columns, write_streamed
from ..results import load, options_attrs, package_versions, to_dataset
from ..system import OmegaSplitModel

__all__ = ["sweep", "sweep_file", "ExecutionOptions", "OutputOptions", "available_cores", "auto_workers",
           "reference_frequencies", "WORKER_THREAD_ENV", "AUTO_PARALLEL_POINTS"]

_MAX_CHUNK = 64  # points per chunk: checkpoint granularity (work lost at an interrupt) and load balance
_MAX_CHUNKS = 2048  # larger sweeps take larger chunks: per-chunk costs (files, messages) stay bounded
_CHUNKS_PER_WORKER = 8
_CHUNK_SECONDS = 0.25  # estimated seconds of a chunk of cheap points: the sweep's process spends ~1 ms per chunk
_BALANCED_SECONDS = 1.0  # estimated seconds of a sweep from which its chunks are of equal cost, not count


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


def _finished(out: Path, key: str, resume: bool, lazy: bool) -> xr.Dataset | None:
    """The finished result at ``out`` (opened lazily: ``lazy``) when resuming a sweep with the
    same fingerprint; refuses (InputError) one made with other settings rather than overwrite it."""
    if not (resume and out.is_file() and not out.with_name(out.name + ".parts").exists()):
        return None
    finished = load(out, lazy=lazy)
    if finished.attrs.get("fingerprint") != key:
        raise InputError(f"{out} is a finished result made with other settings (model, speeds, harmonics, "
                         "samples, stability or method), and resuming would overwrite it; rerun with "
                         "the settings it was made with, give another --out (out=) file, or drop "
                         "--resume (resume=False) to replace it")
    return finished


def sweep(model, omega, harmonics: int, samples: int | None = None, stability: bool | str = True,
          method: str | None = None, *,
          parameters: Mapping[str, Sequence] | None = None, workers: int = 1, out=None, resume: bool = False,
          progress: bool | None | Callable[[int, int], None] = None, execution: ExecutionOptions | None = None,
          output: OutputOptions | None = None) -> xr.Dataset:
    """Periodic solution and stability at every speed (and parameter grid point).

    model: a :class:`periodyn.OmegaSplitModel`, a callable omega (rad/s) -> RheoLinear, or,
        with ``parameters``, a builder called as ``model(**point)`` returning either.
    omega: speeds (k,), rad/s, > 0. harmonics: m >= 1. samples: p (resamples an
        OmegaSplitModel; None keeps the model's). stability: True (= "auto"), False, or a
        stability method (:func:`periodyn.stability.methods.names`); method: its deprecated name.
    parameters: grid ``{name: values}``; the result gets one dimension per name, in order.
    workers: processes (1 = in this process, 0 = all cores).
    out: result file; chunks are checkpointed in ``<out>.parts/`` and ``resume=True``
        continues an interrupted sweep, recomputing only missing points (a finished file
        made with other settings is refused, never overwritten).
    progress: None (bar on a terminal, lines otherwise, after 1 s), False, True, or a
        callable (done, total).
    execution: :class:`ExecutionOptions` (Dask scheduler, chunk size).
    output: :class:`OutputOptions` (name, reference frequency, output units, sweep file text).

    Returns the dataset described in :mod:`periodyn.results` (also written to ``out``; read
    lazily from ``out`` when the results stream, see :class:`OutputOptions`).
    """
    started = time.perf_counter()
    announce_compiles(None if progress is False or callable(progress) else sys.stderr)
    execution = execution if execution is not None else ExecutionOptions()
    output = output if output is not None else OutputOptions()
    if not isinstance(execution, ExecutionOptions) or not isinstance(output, OutputOptions):
        raise InputError("execution= takes a periodyn.ExecutionOptions and output= a periodyn.OutputOptions")
    w = check_speeds(omega)
    m = check_int("harmonics", harmonics, 1)
    p = None if samples is None else check_int("samples", samples, 1)
    stability, method = stability_choice(stability, method)
    workers = check_int("workers", workers, 0) or available_cores()
    if resume and out is None:
        raise InputError("resume=True needs out=<result file>: the checkpoints live in <out>.parts/")
    grid_names, grid_values = _check_grid(model, parameters)
    out = None if out is None else Path(out)
    if execution.scheduler is None and workers > 1:
        start_server_early(execution)  # where workers are not forked from here: their fork server warms up meanwhile
    with sweep_guard(out):  # out checked and locked before any computing; Ctrl-C stops between chunks
        source = ModelSource(model, grid_names, grid_values, p)
        first = (0,) * len(grid_names)
        with np.errstate(all="ignore"):  # an overflowing model gives failed points, reported per point
            probe = source.system(first, float(w[0]))
        first_model = source.model_at(first)
        reference = output.reference
        if reference is None:
            reference = next(iter(reference_frequencies(first_model).items()), None)
        units = output.units_for(probe.output_names, first_model)
        job = Job(source, w, m, stability, method, len(probe.output_names), 2 * probe.n)
        model_name = output.name or getattr(first_model, "name", None) or getattr(model, "__name__", "model")
        options = {"model": model_name, "harmonics": m, "samples": probe.samples, "stability": stability,
                   "method": method, "parameters": list(grid_names)}
        total = int(np.prod(job.shape))
        backend = "dask" if execution.scheduler is not None else "processes" if workers > 1 else "serial"

        checkpoint = None
        streamed = out is not None and (output.stream if output.stream is not None else total >= STREAM_POINTS)
        if streamed:  # no result values kept here: they go to the checkpoints, the file is written from them
            collected = Tally(total, Checkpoint.file_name)
        else:
            collected = Collected(job.empty(total))
            collected.arrays["index"][:] = np.arange(total)
        if out is not None:
            key = fingerprint(job, options, output.sweep_file_text or model_identity(model))
            finished = _finished(out, key, resume, streamed)
            if finished is not None:
                return finished
            checkpoint = Checkpoint(out, key, resume, job.coordinates)
            for chunk in checkpoint.chunks():
                collected.add(chunk)
        pending = np.flatnonzero(~collected.done)
        # several chunks per worker balance the load: of equal count, or of about equal
        # estimated cost in a sweep long enough to gain from it (at low speeds a point may
        # cost 30x one at high speeds), of up to _MAX_CHUNK points or, for cheap points, about
        # _CHUNK_SECONDS; the serial path takes chunks of _MAX_CHUNK points (more beyond
        # _MAX_CHUNKS chunks), an explicit chunk_size is taken as given
        if backend != "serial":
            job.speed_cost = job.speed_costs()
        largest = max(_MAX_CHUNK, math.ceil(total / _MAX_CHUNKS))
        if execution.chunk_size or backend == "serial":
            chunks = split(pending, execution.chunk_size or largest)
        else:
            costs = job.point_costs(pending)
            largest = max(largest, int(_CHUNK_SECONDS * len(costs) / max(costs.sum(), 1e-300)))
            per_chunk = costs.sum() / (_CHUNKS_PER_WORKER * workers)
            size = max(1, min(largest, math.ceil(len(pending) / (_CHUNKS_PER_WORKER * workers))))
            chunks = split(pending, size, costs, per_chunk if costs.sum() >= _BALANCED_SECONDS else np.inf)

        if progress is not False and not callable(progress) and len(pending) and not kernels_cached():
            print(f"periodyn: {COMPILE_NOTE}", file=sys.stderr, flush=True)
        check_interrupt()
        if backend == "processes" and checkpoint is not None:
            job.writer, job.streamed = checkpoint, streamed  # the workers write their chunks' checkpoints
        results = BACKENDS[backend](job, chunks, workers, execution)  # may fork workers: before any other thread
        writer_loaded = out is None or backend == "serial"
        with contextlib.closing(results), Progress(total, total - len(pending), f"sweep {model_name}",
                                                   progress) as bar:
            for chunk in results:
                if not chunk.pop("written", False) and checkpoint is not None:
                    checkpoint.write(chunk)
                collected.add(chunk)
                bar.update(len(chunk["index"]))
                check_interrupt()
                if not writer_loaded:  # while the workers solve
                    writer_loaded = _load_writer()

        failed, methods = collected.counts()
        attrs = {"title": f"periodyn sweep of {model_name}", "created_by": "periodyn.sweep",
                 **options_attrs(options), "backend": backend, "workers": workers if backend != "serial" else 1,
                 "points": total, "points_computed": int(len(pending)), "failed_points": failed,
                 "stability_methods": _method_counts(methods, method, stability),
                 "elapsed_s": time.perf_counter() - started,
                 "package_versions": json.dumps(package_versions(), sort_keys=True),
                 "sweep_file_text": output.sweep_file_text or ""}
        if checkpoint is not None:
            attrs["fingerprint"] = checkpoint.fingerprint
        columns = streamed_columns(job, checkpoint.parts, collected) if streamed else collected.arrays
        ds = to_dataset(columns, omega=w, harmonics=m, outputs=probe.output_names, output_units=units,
                        grid=dict(zip(grid_names, grid_values)), reference=reference, attrs=attrs)
        if streamed:
            write_streamed(ds, checkpoint.finish)
            return load(out, lazy=True)
        if checkpoint is not None:
            checkpoint.finish(ds)
        return ds


def _load_writer() -> bool:
    """Import what writing the result file imports (h5netcdf, h5py, and distributed, which
    xarray's writer imports to look for a Dask client: 0.2 of the 0.4 s that writing a
    first file took), here while the workers solve rather than after the last chunk. In
    this (the main) thread: h5py imported by a second thread deadlocked against
    threadpoolctl's scan of the loaded libraries in this one (the dynamic loader's lock
    against the GIL), under the oldest dependencies."""
    import importlib

    for name in ("h5py", "h5netcdf", "distributed"):
        with contextlib.suppress(ImportError):
            importlib.import_module(name)
    return True


def _method_counts(methods: dict[str, int], method: str, stability: bool) -> str:
    """Dataset attribute: how many points each stability method served ({method: points}),
    and the rule of a method that chooses per point (its registry entry's ``rule``, e.g. "auto")."""
    if not stability:
        return "none (stability off)"
    text = ", ".join(f"{name or 'failed'} {methods[name]}" for name in sorted(methods))
    rule = method_named(method).rule
    return f"{text}; {rule}" if rule else text


def sweep_file(spec, *, omega=None, out=None, workers: int | str = 1, scheduler=None, resume: bool = False,
               progress=None, chunk_size: int | None = None) -> xr.Dataset:
    """Run a validated sweep file (:class:`periodyn.studies.sweep.SweepSpec`); ``omega``
    (start, stop, num) in the file's unit replaces its speeds; ``workers="auto"``:
    see :func:`auto_workers`."""
    compile_ahead()  # a first run compiles the solver beside the model's kernels
    if workers == "auto":
        workers = auto_workers(spec.points(omega))
    if scheduler is None and workers != 1:
        start_server_early()  # where workers are not forked from here: warms up while the model is built
    plan = spec.plan(omega)
    return sweep(plan.model, plan.omega, spec.harmonics, spec.samples, spec.method if spec.stability else False,
                 parameters=plan.parameters, workers=workers, out=out, resume=resume, progress=progress,
                 execution=ExecutionOptions(scheduler, chunk_size),
                 output=OutputOptions(spec.example, plan.reference, spec.output_units or None, spec.text))
