"""Checkpoints of a sweep writing ``out``: finished chunks in ``<out>.parts/`` until merged,
and the fingerprint of the sweep settings that a resume must match. Each chunk carries
that fingerprint and the coordinates (speed, grid parameters) of its points, so a chunk
of another sweep, or one whose points lie elsewhere, is never merged."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import warnings
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterator

import numpy as np
import xarray as xr

from ..errors import InputError
from ..results import STATUS_SOLVED, save
from ..system import OmegaSplitModel
from .job import Job

__all__ = ["Checkpoint", "Collected", "fingerprint", "model_identity", "split"]


class Checkpoint:
    """Finished chunks of the sweep writing ``out``, kept in ``<out>.parts/`` until merged.

    Each chunk is an .npz file written under a temporary name and renamed, so a killed
    process leaves either a whole chunk or none; ``manifest.json`` holds the fingerprint
    of the sweep settings so a resume refuses parts of a different sweep, and each chunk
    holds it too (``_fingerprint``) with its points' coordinates (``_at_<name>``, from
    ``coordinates(indices)``): a chunk whose either differs is dropped with a warning and
    its points recomputed.
    """

    def __init__(self, out: Path, fingerprint: str, resume: bool,
                 coordinates: Callable[[np.ndarray], dict[str, np.ndarray]]):
        self.out = out
        self.parts = out.with_name(out.name + ".parts")
        self.fingerprint = fingerprint
        self.coordinates = coordinates
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
        """Chunks already finished: their result columns, without the stamp. Unreadable
        files, and chunks of another sweep or at other points, are dropped (with a warning
        for the latter) and recomputed."""
        if not self.parts.exists():
            return
        for path in sorted(self.parts.glob("chunk-*.npz")):
            try:
                with np.load(path, allow_pickle=False) as data:
                    chunk = {k: data[k] for k in data.files}
            except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile):
                path.unlink(missing_ok=True)
                continue
            problem = self._foreign(chunk)
            if problem:
                warnings.warn(f"checkpoint {path} {problem}; it is dropped and its points are computed again",
                              stacklevel=2)
                path.unlink(missing_ok=True)
                continue
            yield {k: v for k, v in chunk.items() if not k.startswith("_")}

    def _foreign(self, chunk: dict[str, np.ndarray]) -> str:
        """Why ``chunk`` is not part of this sweep ('' when it is)."""
        if "_fingerprint" not in chunk or "index" not in chunk:
            return "carries no sweep fingerprint (written by an older periodyn or another program)"
        if str(chunk["_fingerprint"]) != self.fingerprint:
            return "belongs to another sweep (other model, speeds, harmonics, samples, stability or method)"
        try:
            expected = self.coordinates(chunk["index"])
        except (ValueError, TypeError, IndexError):
            return "holds point indices outside this sweep"
        for name, values in expected.items():
            stored = chunk.get(f"_at_{name}")
            if stored is None or stored.shape != values.shape or not np.array_equal(stored, values):
                return f"holds points at other values of {name} than this sweep's"
        return ""

    @staticmethod
    def file_name(chunk: dict[str, np.ndarray]) -> str:
        """Name of the checkpoint file of ``chunk`` in the parts folder."""
        return f"chunk-{int(chunk['index'][0]):010d}-{len(chunk['index'])}.npz"

    def write(self, chunk: dict[str, np.ndarray]) -> None:
        """Store one finished chunk with the sweep's fingerprint and its points' coordinates
        (the folder and its manifest are made with the first). An OS error (no space, no
        permission) is an InputError naming the folder and the fix."""
        stamp = {"_fingerprint": np.array(self.fingerprint),
                 **{f"_at_{k}": v for k, v in self.coordinates(chunk["index"]).items()}}
        name = self.file_name(chunk)
        try:
            if not self.manifest.exists():
                self.parts.mkdir(parents=True, exist_ok=True)
                self._atomic_write(self.manifest,
                                   lambda f: f.write(json.dumps({"fingerprint": self.fingerprint}).encode()))
            self._atomic_write(self.parts / name, lambda f: np.savez(f, **chunk, **stamp))
        except OSError as exc:
            raise InputError(f"cannot write the checkpoint {self.parts / name} ({exc.strerror or exc}); free space "
                             f"on that disk or make {self.parts.parent} writable, then continue with --resume "
                             "(resume=True); the chunks finished so far are kept") from None

    def finish(self, ds: xr.Dataset) -> None:
        """Write the merged result file, then drop the parts."""
        save(ds, self.out)
        shutil.rmtree(self.parts, ignore_errors=True)



@dataclass
class Collected:
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

    def counts(self) -> tuple[int, dict[str, int]]:
        """(failed points, {stability method: points})."""
        names, counts = np.unique(np.asarray(self.arrays["stability_method"], dtype=str), return_counts=True)
        return int((self.arrays["status"] != STATUS_SOLVED).sum()), dict(zip(names.tolist(), counts.tolist()))



def model_identity(model) -> str:
    if isinstance(model, OmegaSplitModel):
        digest = hashlib.sha256()
        for a in (model.mass, model.damping, model.stiffness, model.force, model.output_maps):
            digest.update(np.ascontiguousarray(a).tobytes())
        digest.update(repr((model.name, model.output_names, model.coordinate_names)).encode())
        return digest.hexdigest()
    return f"{getattr(model, '__module__', '')}.{getattr(model, '__qualname__', type(model).__qualname__)}"


def fingerprint(job: Job, options: dict, identity: str) -> str:
    digest = hashlib.sha256(json.dumps(options, sort_keys=True).encode())
    digest.update(identity.encode())
    digest.update(job.omega.tobytes())
    for name, values in zip(job.source.grid_names, job.source.grid_values):
        digest.update(name.encode())
        digest.update(np.asarray(values).tobytes())
    return digest.hexdigest()


def split(indices: np.ndarray, chunk_size: int, costs: np.ndarray | None = None,
          chunk_cost: float = np.inf) -> list[np.ndarray]:
    """Consecutive chunks of ``indices`` with at most ``chunk_size`` points each; with
    ``costs`` (estimated seconds per point, same length), a chunk also ends once its cost
    reaches ``chunk_cost``, so that chunks of slow points hold fewer of them."""
    if costs is None or not np.isfinite(chunk_cost):
        return [indices[i:i + chunk_size] for i in range(0, len(indices), chunk_size)]
    chunks, start, spent = [], 0, 0.0
    for i, cost in enumerate(costs):
        spent += cost
        if i + 1 - start == chunk_size or spent >= chunk_cost:
            chunks.append(indices[start:i + 1])
            start, spent = i + 1, 0.0
    if start < len(indices):
        chunks.append(indices[start:])
    return chunks

