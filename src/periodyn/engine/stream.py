"""Results streamed to the output: a sweep writing ``out`` keeps no result values in its
own process. Finished chunks go to their checkpoint files (:mod:`periodyn.engine.checkpoint`)
as they arrive, the sweep's process keeps only a :class:`Tally` (which points are done,
the counts its attributes report, where each chunk lies), and the result file is written
block by block from the checkpoint files: every variable is a Dask array whose blocks (about
:data:`BLOCK_POINTS` points each, a contiguous range of the flat point index) are read from
the chunks that hold them, each on its own (so that none waits in memory for another). Client memory is then about one
block plus a few bytes per point (the ``done`` flags, the chunk list), whatever the number of
points; the values in the file are the same as those of a sweep assembled in memory. Local
worker processes write their chunks' checkpoint files themselves and send back only a
:func:`receipt`, so the sweep's process does no per-point work for them.
"""

from __future__ import annotations

import math
from collections import Counter
from pathlib import Path
from typing import Callable

import numpy as np

from ..results import STATUS_SOLVED
from .job import Job

__all__ = ["Tally", "receipt", "BLOCK_POINTS", "STREAM_POINTS", "streamed_columns", "write_streamed"]

#: points per block of the result file written from the checkpoints (memory: one block)
BLOCK_POINTS = 1 << 13
#: sweeps writing ``out`` with this many points or more stream by default (OutputOptions.stream)
STREAM_POINTS = 200_000
_TEXT = ("message", "stability_method")


def receipt(chunk: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """What a worker that wrote ``chunk`` to its checkpoint file sends back: the columns a
    :class:`Tally` reads, marked ``written``."""
    return {"written": np.True_, **{name: chunk[name] for name in ("index", "status", *_TEXT)}}


class Tally:
    """What the sweep's process keeps of the finished chunks when results stream: the points
    done, the failed points, the points per stability method, the widest text (UTF-8 bytes)
    and, per chunk, its smallest and largest point index and checkpoint file name."""

    def __init__(self, total: int, file_name: Callable[[dict], str]):
        self.done = np.zeros(total, dtype=bool)
        self.failed = 0
        self.methods: Counter = Counter()
        self.widths = dict.fromkeys(_TEXT, 1)
        self.placed: list[tuple[int, int, str]] = []
        self._file_name = file_name

    def add(self, chunk: dict[str, np.ndarray]) -> None:
        index = chunk["index"]
        self.done[index] = True
        self.failed += int((chunk["status"] != STATUS_SOLVED).sum())
        names, counts = np.unique(np.asarray(chunk["stability_method"], dtype=str), return_counts=True)
        self.methods.update(dict(zip(names.tolist(), counts.tolist())))
        for name in _TEXT:
            encoded = np.char.encode(np.asarray(chunk[name], dtype=str), "utf-8")
            self.widths[name] = max(self.widths[name], encoded.dtype.itemsize)
        self.placed.append((int(index.min()), int(index.max()), self._file_name(chunk)))

    def counts(self) -> tuple[int, dict[str, int]]:
        """(failed points, {stability method: points})."""
        return self.failed, dict(self.methods)


def _block_chunks(shape: tuple[int, ...], target: int) -> tuple[int, tuple[tuple[int, ...], ...]]:
    """(axis, Dask chunks over the point dimensions ``shape``): blocks of at most about
    ``target`` points that are contiguous in flat C order: size 1 along the axes before
    ``axis``, whole along the axes after it."""
    suffix = [math.prod(shape[j + 1:]) for j in range(len(shape))]
    axis = next(j for j in range(len(shape)) if suffix[j] <= target)
    step = max(1, target // suffix[axis])
    chunks = [(1,) * shape[j] for j in range(axis)]
    chunks.append(tuple(min(step, shape[axis] - s) for s in range(0, shape[axis], step)))
    chunks += [(shape[j],) for j in range(axis + 1, len(shape))]
    return axis, tuple(chunks)


def _read_block(parts: Path, placed: np.ndarray, names: list[str], start: int, stop: int,
                layout: dict[str, tuple[tuple[int, ...], np.dtype, object]]) -> dict[str, np.ndarray]:
    """Every column (flat, points start..stop-1) read from the checkpoint chunks that hold them."""
    block = {name: np.full((stop - start, *trailing), fill, dtype=dtype) for name, (trailing, dtype, fill)
             in layout.items()}
    for i in np.flatnonzero((placed[:, 0] < stop) & (placed[:, 1] >= start)):
        with np.load(parts / names[i], allow_pickle=False) as data:
            index = data["index"]
            keep = (index >= start) & (index < stop)
            rows = index[keep] - start
            for name, (_, dtype, _) in layout.items():
                values = data[name][keep]
                if name in _TEXT:
                    values = np.char.encode(values.astype(str), "utf-8")
                block[name][rows] = values.astype(dtype, copy=False)
    return block


def streamed_columns(job: Job, parts: Path, tally: Tally, block_points: int | None = None) -> dict:
    """{column: Dask array of shape (*grid, n_omega, ...)}: the sweep's result columns read
    lazily from the checkpoint chunks in ``parts`` (text columns as UTF-8 bytes, to be
    written with ``_Encoding = utf-8``); blocks of ``block_points`` (default
    :data:`BLOCK_POINTS`) points."""
    import dask
    import dask.array as da

    empty = job.empty(1)
    layout = {}
    for name, column in empty.items():
        if name == "index":
            continue
        dtype = np.dtype(f"S{tally.widths[name]}") if name in _TEXT else column.dtype
        fill = b"" if name in _TEXT else column[0]
        layout[name] = (column.shape[1:], dtype, fill)
    placed = np.array([(a, b) for a, b, _ in tally.placed], dtype=np.int64).reshape(-1, 2)
    names = [name for _, _, name in tally.placed]
    shape = job.shape
    axis, chunks = _block_chunks(shape, block_points or BLOCK_POINTS)
    starts = [np.cumsum((0,) + c[:-1]) for c in chunks]
    read = dask.delayed(_read_block, pure=True)

    def build(prefix: tuple[int, ...]) -> dict:
        """{column: Dask array} of the blocks below the block-index ``prefix``."""
        depth = len(prefix)
        if depth == len(shape):
            corner = tuple(int(starts[d][i]) for d, i in enumerate(prefix))
            sizes = tuple(chunks[d][i] for d, i in enumerate(prefix))
            start = int(np.ravel_multi_index(corner, shape))
            stop = start + math.prod(sizes)  # each variable read on its own: a block is written, then freed
            return {name: da.from_delayed(read(parts, placed, names, start, stop, {name: spec})[name],
                                          (stop - start, *spec[0]), spec[1]).reshape(sizes + spec[0])
                    for name, spec in layout.items()}
        parts_ = [build(prefix + (i,)) for i in range(len(chunks[depth]))]
        if len(parts_) == 1:
            return parts_[0]
        return {name: da.concatenate([p[name] for p in parts_], axis=depth) for name in layout}

    return build(())


def write_streamed(ds, save: Callable) -> None:
    """``save(ds)`` of a dataset of streamed columns, one block at a time in this thread
    (the text variables marked as UTF-8 bytes, read back as text)."""
    import dask

    for name in _TEXT:
        ds[name].attrs["_Encoding"] = "utf-8"
    with dask.config.set(scheduler="synchronous"):
        save(ds)
