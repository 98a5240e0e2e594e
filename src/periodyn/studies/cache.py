"""The one "is this result current" rule of every study kind (sweep, continuation,
transient, campbell): a result file is current iff its attribute ``study_fingerprint``
equals the fingerprint of the request, a hash of the study file as parsed (its TOML
document without ``description``; comments and layout do not count), the inputs it
names (a rotor file's document) and the range replacing the file's (``--omega``).

:func:`periodyn.studies.spec.ensure` reads a current file and recomputes any other;
``--resume`` (:func:`finished`) reads a current file and refuses, never overwrites, a
finished file made otherwise.
"""

from __future__ import annotations

import hashlib
import json
import tomllib
from pathlib import Path

from ..errors import InputError

__all__ = ["FINGERPRINT", "KIND", "fingerprint", "stamp", "stored", "is_current", "finished", "discard_stale"]

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
