"""The "is this current" rules of the study files: results and built models.

Results, every study kind (sweep, continuation, transient, campbell): a result file is
current iff its attribute ``study_fingerprint`` equals the fingerprint of the request, a
hash of the study file as parsed (its TOML document without ``description``; comments and
layout do not count), the inputs it names (a rotor file's document) and the range
replacing the file's (``--omega``). :func:`periodyn.studies.spec.ensure` reads a current
file and recomputes any other; ``--resume`` (:func:`finished`) reads a current file and
refuses, never overwrites, a finished file made otherwise.

Built models (:func:`cached_model`): the OmegaSplitModel a sweep file builds is kept in
``$PERIODYN_CACHE_DIR/models`` (default ``~/.cache/periodyn/models``, or under
``$XDG_CACHE_HOME``) as one ``.npz`` of its arrays and names, current iff its name is the
fingerprint of what the build reads and runs: the study file's document without
``description`` and without the ``[sweep]`` keys other than ``samples``, the inputs it
names, and the code (a hash of every source file of periodyn, and the Python, NumPy and
Numba versions). A second sweep of the same model (another range, a resumed or repeated
run) then starts without building it: for the Cardan shaft 1.6 s of CPU less per run,
for a slider-crank of 128 rod elements about 10 s. ``PERIODYN_MODEL_CACHE=off`` builds
every time; the cache keeps at most MODEL_CACHE_BYTES, the least recently used dropped.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import tempfile
import time
import tomllib
import zipfile
from pathlib import Path

import numpy as np

from ..engine.server import code_version
from ..errors import InputError
from ..system import OmegaSplitModel

__all__ = ["FINGERPRINT", "KIND", "fingerprint", "stamp", "stored", "is_current", "finished", "discard_stale",
           "cached_model", "model_fingerprint", "model_cache_dir", "MODEL_CACHE_BYTES"]

FINGERPRINT = "study_fingerprint"
KIND = "study_kind"


def fingerprint(spec, omega=None) -> str:
    """SHA-256 of the request: ``spec`` (a parsed study file, ``spec.kind``), the inputs
    it names (``spec.inputs``) and the range that replaces the file's (``spec.extent``)."""
    document = tomllib.loads(spec.text)
    document.pop("description", None)
    request = {"kind": spec.kind, "study": document, "inputs": spec.inputs, "range": spec.extent(omega)}
    return hashlib.sha256(json.dumps(request, sort_keys=True, default=str).encode()).hexdigest()


def stamp(spec, omega=None) -> dict[str, str]:
    """The attributes a result file of this request carries."""
    return {FINGERPRINT: fingerprint(spec, omega), KIND: spec.kind}


def stored(path) -> tuple[str | None, str | None]:
    """(fingerprint, kind) a result file carries; (None, None) when it has none or is unreadable."""
    from ..results import root_attrs

    try:
        attrs = root_attrs(path)
        return attrs.get(FINGERPRINT), attrs.get(KIND)
    except (OSError, ValueError, KeyError, RuntimeError):  # RuntimeError: a damaged HDF5 structure
        return None, None


def is_current(path, spec, omega=None) -> bool:
    """Whether ``path`` holds the finished result of this request."""
    path = Path(path)
    return path.is_file() and stored(path)[0] == fingerprint(spec, omega)


def finished(path, spec, omega=None, resume: bool = False) -> bool:
    """With ``resume``: True when ``path`` is the finished result of this request (read it,
    do not compute); InputError when it is a finished result made otherwise. False when
    there is nothing finished to resume (no file, or an interrupted sweep's
    ``<path>.parts`` beside it) or without ``resume``."""
    path = Path(path)
    if not resume or not path.is_file() or path.with_name(path.name + ".parts").exists():
        return False
    key, kind = stored(path)
    if key == fingerprint(spec, omega):
        return True
    if kind != spec.kind:
        raise InputError(f"{path} is not a {spec.kind} study result ({f'a {kind} result' if kind else 'no study'} "
                         "made it), and resuming would overwrite it; give another --out file, or drop --resume "
                         "to replace it")
    raise InputError(f"{path} is a finished study made with other settings (study file, inputs or --omega range), "
                     "and resuming would overwrite it; rerun with the settings it was made with, give another "
                     "--out file, or drop --resume to replace it")


def discard_stale(path, spec, omega=None) -> None:
    """Remove ``path`` unless it is current (ensure recomputes it)."""
    path = Path(path)
    if path.is_file() and not is_current(path, spec, omega):
        path.unlink()


#: bytes the built-model cache keeps at most (the least recently used models are dropped)
MODEL_CACHE_BYTES = 2 * 1024**3
_ARRAYS = ("mass", "damping", "stiffness", "force", "output_maps")


def model_cache_dir() -> Path | None:
    """The folder of the built-model cache; None where ``PERIODYN_MODEL_CACHE=off``."""
    if os.environ.get("PERIODYN_MODEL_CACHE", "").lower() in ("off", "0", "no", "false"):
        return None
    root = os.environ.get("PERIODYN_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "periodyn")
    return Path(root) / "models"


def model_fingerprint(spec) -> str:
    """SHA-256 of what building ``spec``'s model reads and runs (module docstring)."""
    document = tomllib.loads(spec.text)
    document.pop("description", None)
    sweep = document.pop("sweep", {})
    request = {"example": spec.example, "study": document, "samples": sweep.get("samples"),
               "inputs": spec.inputs, "code": code_version()}
    return hashlib.sha256(json.dumps(request, sort_keys=True, default=str).encode()).hexdigest()


def cached_model(spec, build, resample=None):
    """The model of ``spec`` from the built-model cache, or ``build()`` stored there. Only an
    OmegaSplitModel whose names and metadata survive JSON unchanged is kept, and one that
    can be resampled only where ``resample(p)`` (the builder with ``samples=p``) restores
    that. A cache that cannot be read or written is passed by: the model is built."""
    folder = model_cache_dir()
    if folder is None:
        return build()
    path = folder / f"{model_fingerprint(spec)}.npz"
    model = _load(path, resample)
    if model is not None:
        return model
    model = build()
    _store(path, model, resample)
    return model


def _load(path: Path, resample) -> OmegaSplitModel | None:
    try:
        with np.load(path, allow_pickle=False) as data:
            about = json.loads(str(data["about"]))
            model = OmegaSplitModel(**{name: data[name] for name in _ARRAYS},
                                    coordinate_names=tuple(about["coordinate_names"]),
                                    output_names=tuple(about["output_names"]), name=about["name"],
                                    rebuild=resample if about["resamples"] else None, metadata=about["metadata"])
    except (OSError, KeyError, TypeError, ValueError, EOFError, zipfile.BadZipFile):  # absent or damaged
        return None
    with contextlib.suppress(OSError):  # recently used (a read-only cache still serves)
        os.utime(path)
    return model


def _store(path: Path, model, resample) -> None:
    if type(model) is not OmegaSplitModel or (model.rebuild is not None and resample is None):
        return  # not a model the cache can give back as built
    about = {"coordinate_names": list(model.coordinate_names), "output_names": list(model.output_names),
             "name": model.name, "metadata": model.metadata, "resamples": model.rebuild is not None}
    try:
        text = json.dumps(about)
        if json.loads(text)["metadata"] != model.metadata:  # tuples, numpy scalars: not kept exactly
            return
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=path.parent, suffix=".npz.tmp")
        with os.fdopen(handle, "wb") as file:
            np.savez(file, about=np.array(text), **{name: getattr(model, name) for name in _ARRAYS})
        os.replace(temporary, path)  # whole or not at all
        _evict(path.parent)
    except (OSError, TypeError, ValueError):  # a read-only or full disk, metadata JSON cannot hold
        return


def _evict(folder: Path) -> None:
    """Drop the least recently used models beyond MODEL_CACHE_BYTES, and the files of writes
    that a crash left unfinished a day ago."""
    for temporary in folder.glob("*.npz.tmp"):
        if temporary.stat().st_mtime < time.time() - 86400:
            temporary.unlink(missing_ok=True)
    entries = sorted(((p.stat().st_mtime, p.stat().st_size, p) for p in folder.glob("*.npz")), reverse=True)
    total = 0
    for _, size, entry in entries:
        total += size
        if total > MODEL_CACHE_BYTES:
            entry.unlink(missing_ok=True)
