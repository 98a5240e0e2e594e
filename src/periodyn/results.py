"""Sweep results: one self-describing xarray Dataset per sweep, stored as netCDF.

Layout (``P`` = the parameter-grid dimensions, in grid order, possibly none):

======================  ==================================  =========================================
variable                dims                                meaning
======================  ==================================  =========================================
``amplitude``           (*P, omega, output)                 half peak-to-peak of each output
``mean``                (*P, omega, output)                 period mean of each output
``harmonics``           (*P, omega, harmonic, output)       complex Fourier coefficients, l = -m..m
``residual``            (*P, omega)                         harmonic-balance residual norm
``exponents``           (*P, omega, exponent)               complex characteristic exponents, rad/s
``multipliers``         (*P, omega, exponent)               complex Floquet multipliers
``max_real_exponent``   (*P, omega)                         largest real part of the exponents, 1/s
``stable``              (*P, omega)                         max_real_exponent < 0
``status``              (*P, omega)                         0 solved, 1 failed (see ``message``)
``message``             (*P, omega)                         why a point failed ('' if solved)
``stability_method``    (*P, omega)                         stability method used ("auto" chooses per point)
``reduced_modes``       (*P, omega)                         modes k of method "reduced" (0: not used there)
``reduced_correction``  (*P, omega)                         its largest Schur correction |d_lambda|, 1/s
``stability_error_bound`` (*P, omega)                       its bound on max_real_exponent * period
``balance_modes``       (*P, omega)                         modes kept by the reduced HB (0: full HB)
``balance_truncation``  (*P, omega)                         harmonics the HB left out, relative (warned above 1e-2)
``hill_truncation``     (*P, omega)                         Hill's edge energy (NaN without Hill; fails above 1e-6)
======================  ==================================  =========================================

Coordinates: ``omega`` (rad/s), one per grid parameter, ``harmonic`` (l), ``output`` (names),
``output_units`` along output (the unit of each output, "" where the model does not say),
``exponent`` (index 0..2n-1), and ``omega_over_<ref>`` along omega when the sweep has a
reference frequency. Failed points hold NaN and ``stable = False``. The columns of
:data:`STABILITY_RECORDS` are in every sweep; where the method "reduced" did not certify
the point (another method, a speed it handed on, no stability) they hold their fill
values: ``reduced_modes`` 0, the two floats NaN; ``balance_modes`` is 0 where the full HB was solved.

:data:`_LAYOUT` below is the one definition of this layout: :func:`empty_columns` (the
per-point columns a sweep fills) and :func:`to_dataset` (the dataset) both read it.

On disk complex variables become real ones with a trailing ``part`` dimension
(``real``, ``imag``) so plain netCDF readers open the file; :func:`load` restores them.
Attributes carry the sweep options, the sweep file's text and the package versions.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import platform
from importlib import metadata
from pathlib import Path
from typing import Callable, TypeVar

import numpy as np
import xarray as xr

from .errors import InputError

__all__ = ["load", "save", "root_attrs", "to_dataset", "empty_columns", "package_versions", "options_attrs", "STATUS_SOLVED",
           "STATUS_FAILED", "STABILITY_RECORDS", "load_groups"]

_T = TypeVar("_T")
STATUS_SOLVED = 0
STATUS_FAILED = 1
_PART = "part"
_COMPLEX_FLAG = "periodyn_complex"
_ENGINE = "h5netcdf"
_DIGEST = "periodyn_sha256"
_CHUNK_BYTES = 1 << 20
_VERSIONED = ("periodyn", "numpy", "scipy", "numba", "pyfftw", "xarray", "h5netcdf", "dask", "distributed")


def package_versions() -> dict[str, str]:
    """Versions of Python and the packages a result depends on (read once per process:
    the package metadata costs about 0.1 s, more than a small sweep)."""
    return dict(_versions())


@functools.lru_cache(maxsize=1)
def _versions() -> tuple[tuple[str, str], ...]:
    versions = [("python", platform.python_version())]
    for name in _VERSIONED:
        try:
            versions.append((name, metadata.version(name)))
        except metadata.PackageNotFoundError:
            versions.append((name, "not installed"))
    return tuple(versions)


def _split_complex(ds: xr.Dataset) -> xr.Dataset:
    out = ds.copy()
    for name, var in ds.data_vars.items():
        if var.dtype.kind == "c":  # var.data: a Dask array (streamed results) stays lazy
            parts = np.stack([var.data.real, var.data.imag], axis=-1)
            out[name] = xr.Variable(var.dims + (_PART,), parts, {**var.attrs, _COMPLEX_FLAG: 1})
    if any(_COMPLEX_FLAG in out[v].attrs for v in out.data_vars):
        out = out.assign_coords({_PART: (_PART, np.array(["real", "imag"]),
                                          {"long_name": "real or imaginary part of a complex variable"})})
    return out


def _join_complex(ds: xr.Dataset) -> xr.Dataset:
    out = ds.copy()
    for name, var in ds.data_vars.items():
        if var.attrs.get(_COMPLEX_FLAG):
            values = var.isel({_PART: 0}).data + 1j * var.isel({_PART: 1}).data
            attrs = {k: v for k, v in var.attrs.items() if k != _COMPLEX_FLAG}
            out[name] = xr.Variable(tuple(d for d in var.dims if d != _PART), values, attrs)
    if _PART in out.dims and not any(_PART in out[v].dims for v in out.data_vars):
        out = out.drop_vars(_PART)
    return out


def _checksummed(ds: xr.Dataset) -> dict:
    """netCDF encoding that stores every array variable chunked with a Fletcher-32 checksum
    (strings as fixed-width characters, so that they are checksummed too): a flipped byte
    in the data becomes a read error rather than a wrong number."""
    encoding = {}
    for name, var in ds.variables.items():
        if not (var.ndim and var.size):
            continue
        if var.dtype.kind in "UOS":
            encoding[name] = {"fletcher32": True, "dtype": "S1"}
        else:  # chunks of whole rows, about 1 MiB (the automatic ones split rows into many small pieces)
            rows = max(1, min(var.shape[0], _CHUNK_BYTES // (var.dtype.itemsize * (var.size // var.shape[0]))))
            encoding[name] = {"fletcher32": True, "chunksizes": (rows, *var.shape[1:])}
    return encoding


def _digest(f) -> str:
    """SHA-256 of every dataset (name, type, shape, stored values) of the open HDF5 file
    ``f``: Fletcher-32 misses some damage (a run of inverted bytes that covers a chunk
    and its checksum), this does not."""
    import h5py

    digest = hashlib.sha256()

    def add(name, obj):
        if isinstance(obj, h5py.Dataset):
            digest.update(f"{name}|{obj.dtype.str}|{obj.shape}|".encode())
            # read in slabs of whole rows (memory bounded for any file); the bytes are those of the whole array
            rows = obj.shape[0] if obj.ndim else 1
            step = max(1, 4 * _CHUNK_BYTES // max(1, obj.dtype.itemsize * (obj.size // max(rows, 1))))
            for start in range(0, rows, step):
                values = obj[start:start + step] if obj.ndim else obj[()]
                if obj.dtype.kind == "O":
                    digest.update(("\0" if start else "").encode() + "\0".join(map(str, np.ravel(values))).encode())
                else:
                    digest.update(np.ascontiguousarray(values))  # its bytes, not copied

    f.visititems(add)
    return digest.hexdigest()


def save(ds: xr.Dataset, path, groups: dict[str, xr.Dataset] | None = None) -> Path:
    """Write a result dataset to ``path`` (netCDF-4 via h5netcdf, every variable with a
    Fletcher-32 checksum and the file's contents with a SHA-256 digest, attribute
    ``periodyn_sha256``) atomically: the file is written beside the target and renamed,
    so a crash never leaves half a file. groups: {name: dataset} written as netCDF groups
    beside ``ds`` in the root (read them with :func:`load_groups`). An OS error (no space,
    no permission) is an InputError naming the path and the fix."""
    import h5py

    path = Path(path)
    tmp = path.with_name(f"{path.name}.{os.getpid()}.partial")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        for i, (group, part) in enumerate([(None, ds), *(groups or {}).items()]):
            split = _split_complex(part)
            split.to_netcdf(tmp, mode="a" if i else "w", group=group, engine=_ENGINE, encoding=_checksummed(split))
        with h5py.File(tmp, "r+") as f:
            f.attrs[_DIGEST] = _digest(f)
        os.replace(tmp, path)
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        raise InputError(f"cannot write the result file {path} ({exc.strerror or exc}); free space on its disk, make "
                         "its folder writable, or give another --out (out=) file") from None
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def load(path, lazy: bool = False) -> xr.Dataset:
    """Read a result file written by :func:`save` (complex variables restored); a
    damaged file (checksum mismatch, broken structure) is an InputError naming it.
    lazy: variables are Dask arrays read from the file when used (for results larger
    than memory)."""
    return _checked(path, lambda f: _open(path, None, lazy))


def load_groups(path) -> tuple[xr.Dataset, dict[str, xr.Dataset]]:
    """The root dataset and {name: dataset} of every netCDF group of a file written by
    :func:`save` with ``groups`` (checked and restored as :func:`load`)."""
    import h5py

    return _checked(path, lambda f: (_open(path, None), {name: _open(path, name) for name, obj in f.items()
                                                         if isinstance(obj, h5py.Group)}))


def root_attrs(path) -> dict:
    """The root attributes of a netCDF file (no data read, no digest checked); OSError,
    ValueError or RuntimeError (a damaged HDF5 structure) when it cannot be opened."""
    with xr.open_dataset(path, engine=_ENGINE) as ds:
        return dict(ds.attrs)


def _open(path: Path, group: str | None, lazy: bool = False) -> xr.Dataset:
    if lazy:
        ds = xr.open_dataset(path, engine=_ENGINE, group=group, chunks={})
    else:
        with xr.open_dataset(path, engine=_ENGINE, group=group) as raw:
            ds = raw.load()
    ds.attrs.pop(_DIGEST, None)
    return _join_complex(ds)


def _checked(path, read: Callable[..., _T]) -> _T:
    """``read(f)`` (f: the open h5py file) after checking the SHA-256 digest :func:`save`
    wrote (a file without one is read unchecked); no file, or damage (digest or Fletcher-32
    mismatch, broken structure), is an InputError naming it."""
    import h5py

    path = Path(path)
    if not path.is_file():
        raise InputError(f"no result file at {path}; run the sweep first (periodyn sweep ... --out {path})")
    try:
        with h5py.File(path, "r") as f:
            stored = f.attrs.get(_DIGEST)
            if stored is not None and (stored.decode() if isinstance(stored, bytes) else str(stored)) != _digest(f):
                raise ValueError("its contents do not match the SHA-256 digest written with it")
            return read(f)
    except (OSError, ValueError, KeyError, RuntimeError, TypeError, IndexError, UnicodeDecodeError) as exc:
        raise InputError(f"{path} is not a readable periodyn result file, or it is damaged ({type(exc).__name__}: "
                         f"{exc}); delete it and run the sweep again (without --resume)") from None


def options_attrs(options: dict) -> dict:
    """Dataset attributes for sweep options: JSON in ``sweep_options`` plus flat scalars."""
    attrs = {"sweep_options": json.dumps(options, sort_keys=True)}
    for key, value in options.items():
        if isinstance(value, bool):
            attrs[key] = int(value)
        elif isinstance(value, (int, float, str)):
            attrs[key] = value
    return attrs


# name, dimensions after the point dimensions, fill value (dtype), attributes; "{units}"
# stands for the output units
_LAYOUT = (
    ("amplitude", ("output",), np.nan, {"long_name": "half peak-to-peak amplitude", "units": "{units}"}),
    ("mean", ("output",), np.nan, {"long_name": "mean over one period", "units": "{units}"}),
    ("harmonics", ("harmonic", "output"), np.nan + 0j,
     {"long_name": "Fourier coefficients y_l of the outputs, y(t) = sum_l y_l exp(i l omega t)", "units": "{units}"}),
    ("residual", (), np.nan, {"long_name": "relative harmonic-balance residual norm", "units": "1"}),
    ("exponents", ("exponent",), np.nan + 0j,
     {"long_name": "characteristic exponents (NaN without stability)", "units": "rad/s"}),
    ("multipliers", ("exponent",), np.nan + 0j, {"long_name": "Floquet multipliers", "units": "1"}),
    ("max_real_exponent", (), np.nan,
     {"long_name": "largest real part of the characteristic exponents", "units": "1/s"}),
    ("stable", (), False, {"long_name": "periodic solution asymptotically stable"}),
    ("status", (), np.int8(STATUS_FAILED),
     {"long_name": "0 solved, 1 failed (see message)", "flag_values": np.array([STATUS_SOLVED, STATUS_FAILED],
                                                                                 dtype=np.int8),
      "flag_meanings": "solved failed"}),
    ("message", (), "", {"long_name": "why the point failed, empty if solved"}),
    ("stability_method", (), "", {"long_name": "stability method used at the point (what method 'auto' chose; "
                                               "empty without stability or where the point failed)"}),
    ("reduced_modes", (), np.int32(0),
     {"long_name": "mean-system modes kept by stability method 'reduced' at the point (0 where it did not "
                   "certify the point: another method, a speed it handed on, no stability or a failed point)",
      "units": "1"}),
    ("reduced_correction", (), np.nan,
     {"long_name": "largest Schur-complement correction |d_lambda| of the exponents corrected by method 'reduced' "
                   "(NaN where it did not certify the point)", "units": "1/s"}),
    ("stability_error_bound", (), np.nan,
     {"long_name": "certified bound of the error of max_real_exponent * period (log of the largest multiplier "
                   "modulus) by method 'reduced': ladder error + 2 |d_lambda| period (NaN where it did not "
                   "certify the point)", "units": "1"}),
    ("balance_modes", (), np.int32(0),
     {"long_name": "mean-system modes kept by the reduced harmonic balance at the point (its residual is that of "
                   "the full HB equations; 0 where the full HB was solved)", "units": "1"}),
    ("balance_truncation", (), np.nan,
     {"long_name": "estimated largest harmonic left out by the harmonic balance relative to the largest kept "
                   "(periodyn.harmonic.truncation; above 1e-2 the amplitudes may be wrong: increase harmonics)",
      "units": "1"}),
    ("hill_truncation", (), np.nan,
     {"long_name": "Hill's truncation indicator: the largest energy fraction of an exponent's eigenvector in the "
                   "outermost harmonics (NaN where no Hill method judged the point; above 1e-6 the point fails)",
      "units": "1"}),
)
#: per-speed columns of the reduced paths (``choose``'s records of a stability method, and the
#: reduced HB's mode count) and the HB and Hill truncation indicators, with their fill values
STABILITY_RECORDS = {name: fill for name, _, fill, _ in _LAYOUT[-6:]}


def _sizes(harmonics: int, n_outputs: int, n_exponents: int) -> dict[str, int]:
    return {"harmonic": 2 * harmonics + 1, "output": n_outputs, "exponent": n_exponents}


def empty_columns(count: int, harmonics: int, n_outputs: int, n_exponents: int) -> dict[str, np.ndarray]:
    """Result columns for ``count`` points: ``index`` (count,) int plus every variable of
    the layout with a leading point axis, filled as failed (NaN, status 1, message '')."""
    sizes = _sizes(harmonics, n_outputs, n_exponents)
    columns = {"index": np.zeros(count, dtype=np.int64)}
    for name, dims, fill, _ in _LAYOUT:
        dtype = object if isinstance(fill, str) else np.asarray(fill).dtype
        columns[name] = np.full((count, *(sizes[d] for d in dims)), fill, dtype=dtype)
    return columns


def _units_text(units: tuple[str, ...]) -> str:
    known = sorted(set(u for u in units if u))
    if len(known) == 1 and all(units):
        return known[0]
    return "per output: see output_units" if known else "not given by the model"


def to_dataset(columns: dict[str, np.ndarray], *, omega: np.ndarray, harmonics: int, outputs: tuple[str, ...],
               output_units: tuple[str, ...] | None = None, grid: dict[str, np.ndarray] | None = None,
               reference: tuple[str, float] | None = None, attrs: dict | None = None) -> xr.Dataset:
    """The sweep dataset from result columns over flat point indices (C order of
    ``(*grid, omega)``, as from :func:`empty_columns`; or already of shape (*grid, omega, ...),
    text as bytes, as from :func:`periodyn.engine.stream.streamed_columns`). omega (k,) rad/s; outputs: names;
    output_units: one unit string per output ('' unknown); grid: {name: values} in order;
    reference: (name, rad/s) adds ``omega_over_<name>``."""
    from .numerics.spectra import harmonic_indices

    grid = dict(grid or {})
    shape = tuple(len(v) for v in grid.values()) + (len(omega),)
    base = tuple(grid) + ("omega",)
    units = tuple(output_units) if output_units is not None else ("",) * len(outputs)
    if len(units) != len(outputs):
        raise InputError(f"{len(units)} output units for {len(outputs)} outputs ({', '.join(outputs)}); "
                         "give one unit per output")
    coords = {"omega": ("omega", np.asarray(omega, float), {"units": "rad/s", "long_name": "driving speed"}),
              "harmonic": ("harmonic", harmonic_indices(harmonics),
                           {"long_name": "harmonic index l of exp(i l omega t)", "units": "1"}),
              "output": ("output", np.array(outputs, dtype=str), {"long_name": "model output"}),
              "output_units": ("output", np.array(units, dtype=str), {"long_name": "unit of each output"}),
              "exponent": ("exponent", np.arange(columns["exponents"].shape[-1]),
                           {"long_name": "characteristic exponent index", "units": "1"})}
    for name, values in grid.items():
        coords[name] = (name, np.asarray(values), {"long_name": f"model parameter {name}"})
    if reference is not None:
        ref_name, ref_value = reference
        coords[f"omega_over_{ref_name}"] = ("omega", np.asarray(omega, float) / ref_value,
                                            {"units": "1", "long_name": f"omega / {ref_name}",
                                             "reference_frequency": ref_value,
                                             "reference_frequency_units": "rad/s"})
    variables, units_text = {}, _units_text(units)
    for name, dims, fill, var_attrs in _LAYOUT:
        values = columns[name]
        if values.ndim == 1 + len(dims):  # flat over the points
            values = values.reshape(shape + values.shape[1:])
        if isinstance(fill, str) and values.dtype.kind not in "US":
            values = values.astype(str)
        filled = {k: (v.format(units=units_text) if isinstance(v, str) else v) for k, v in var_attrs.items()}
        variables[name] = (base + dims, values, filled)
    return xr.Dataset(variables, coords=coords, attrs=dict(attrs or {}))
