"""Option objects of :func:`periodyn.sweep`: small frozen dataclasses that validate
themselves on construction (an :class:`~periodyn.errors.InputError` naming the field and
the fix). The common settings (harmonics, samples, stability, method, parameters, workers,
out, resume, progress) stay keywords of ``sweep``; the rest live here."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["ExecutionOptions", "OutputOptions", "check_int", "WORKER_STARTS"]

#: ways local worker processes start (ExecutionOptions.worker_start)
WORKER_STARTS = ("auto", "forkserver", "spawn")


def check_int(name: str, value, minimum: int) -> int:
    """``value`` as an int >= minimum, else InputError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


@dataclass(frozen=True)
class ExecutionOptions:
    """Where and in what pieces the points are solved.

    scheduler: None (this process or ``workers`` local processes), a Dask ``Client``, a
        scheduler address ("tcp://host:8786"), or "local" (a LocalCluster of ``workers``
        one-thread processes).
    chunk_size: points per chunk (checkpoint granularity and load balance), or None for
        up to 64 (cheap points: about 0.25 s of estimated work) with 8+ chunks per worker.
    eager_workers: start the local worker processes whatever the sweep's length; by
        default they start at once where the chunks' estimated cost shows they pay, else
        only when they would finish the chunks left after the first two (solved in the
        calling process, the second timed) sooner than the calling process alone, counting
        their start as measured on this process's previous pool.
    worker_start: how local worker processes start: "auto" (forked from this process once
        the model is built, where that is safe, else from a fork server, else spawned),
        "forkserver" (a fork server, where available, else spawned) or "spawn".
    """

    scheduler: Any = None
    chunk_size: int | None = None
    eager_workers: bool = False
    worker_start: str = "auto"

    def __post_init__(self):
        if self.chunk_size is not None:
            object.__setattr__(self, "chunk_size", check_int("ExecutionOptions.chunk_size", self.chunk_size, 1))
        if not isinstance(self.eager_workers, bool):
            raise InputError(f"ExecutionOptions.eager_workers must be True or False, got {self.eager_workers!r}")
        if self.worker_start not in WORKER_STARTS:
            raise InputError(f"ExecutionOptions.worker_start must be one of {', '.join(map(repr, WORKER_STARTS))}, "
                             f"got {self.worker_start!r}")
        if self.scheduler is not None and not isinstance(self.scheduler, str) and not hasattr(self.scheduler, "submit"):
            raise InputError(f"ExecutionOptions.scheduler must be a Dask Client, a scheduler address such as "
                             f"'tcp://host:8786', or 'local', got {type(self.scheduler).__name__}")


@dataclass(frozen=True)
class OutputOptions:
    """How the results describe themselves.

    name: model name in the title and attributes (default: the model's ``name``).
    reference: (name, rad/s) adds the coordinate ``omega_over_<name>`` (default: the
        model's first ``metadata`` entry named omega*).
    output_units: unit of each output, a sequence in output order or {output: unit}
        (default: the model's ``metadata["output_units"]``, else not given).
    sweep_file_text: text of the sweep file the sweep came from (kept in the attributes;
        identifies the sweep for ``resume``).
    stream: with ``out``, keep no result values in this process: chunks go to their
        checkpoint files, the result file is written from them block by block and the
        sweep returns it opened lazily (:mod:`periodyn.engine.stream`); None: from
        ``STREAM_POINTS`` points on.
    """

    name: str | None = None
    reference: tuple[str, float] | None = None
    output_units: Any = None
    sweep_file_text: str | None = None
    stream: bool | None = None

    def __post_init__(self):
        if self.name is not None and not isinstance(self.name, str):
            raise InputError(f"OutputOptions.name must be a string, got {type(self.name).__name__}")
        if self.reference is not None:
            ok = (isinstance(self.reference, (tuple, list)) and len(self.reference) == 2
                  and isinstance(self.reference[0], str) and isinstance(self.reference[1], (int, float, np.number))
                  and np.isfinite(self.reference[1]) and self.reference[1] > 0)
            if not ok:
                raise InputError("OutputOptions.reference must be (name, frequency in rad/s > 0), e.g. "
                                 f"('omega0', 3.13), got {self.reference!r}")
            object.__setattr__(self, "reference", (self.reference[0], float(self.reference[1])))
        units = self.output_units
        if units is not None:
            values = units.values() if isinstance(units, Mapping) else units
            if isinstance(units, str) or not all(isinstance(u, str) for u in values):
                raise InputError("OutputOptions.output_units must be a list of unit strings in output order or "
                                 f"{{output: unit}}, got {units!r}")
        if self.sweep_file_text is not None and not isinstance(self.sweep_file_text, str):
            raise InputError("OutputOptions.sweep_file_text must be the text of a sweep file")
        if self.stream is not None and not isinstance(self.stream, bool):
            raise InputError(f"OutputOptions.stream must be True, False or None (automatic), got {self.stream!r}")

    def units_for(self, outputs: tuple[str, ...], model) -> tuple[str, ...]:
        """One unit string per output ('' where unknown): these options, else the model's
        ``metadata["output_units"]``."""
        units = self.output_units
        if units is None:
            meta = getattr(model, "metadata", None)
            units = meta.get("output_units") if isinstance(meta, Mapping) else None
        if units is None:
            return ("",) * len(outputs)
        if isinstance(units, Mapping):
            unknown = sorted(set(units) - set(outputs))
            if unknown:
                raise InputError(f"output_units names {', '.join(unknown)}, which the model does not output; "
                                 f"its outputs: {', '.join(outputs)}")
            return tuple(str(units.get(o, "")) for o in outputs)
        units = tuple(str(u) for u in units)
        if len(units) != len(outputs):
            raise InputError(f"{len(units)} output units for {len(outputs)} outputs ({', '.join(outputs)}); "
                             "give one unit per output")
        return units
