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
======================  ==================================  =========================================

Coordinates: ``omega`` (rad/s), one per grid parameter, ``harmonic`` (l), ``output`` (names),
``exponent`` (index 0..2n-1), and ``omega_over_<ref>`` along omega when the sweep has a
reference frequency. Failed points hold NaN and ``stable = False``.

On disk complex variables become real ones with a trailing ``part`` dimension
(``real``, ``imag``) so plain netCDF readers open the file; :func:`load` restores them.
Attributes carry the sweep options, the sweep file's text and the package versions.
"""

from __future__ import annotations

import json
import os
import platform
from importlib import metadata
from pathlib import Path

import numpy as np
import xarray as xr

from .errors import InputError

__all__ = ["load", "save", "ensure", "package_versions", "STATUS_SOLVED", "STATUS_FAILED"]

STATUS_SOLVED = 0
STATUS_FAILED = 1
_PART = "part"
_COMPLEX_FLAG = "periodyn_complex"
_ENGINE = "h5netcdf"
_VERSIONED = ("periodyn", "numpy", "scipy", "numba", "pyfftw", "xarray", "h5netcdf", "dask", "distributed")


def package_versions() -> dict[str, str]:
    """Versions of Python and the packages a result depends on."""
    versions = {"python": platform.python_version()}
    for name in _VERSIONED:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = "not installed"
    return versions


def _split_complex(ds: xr.Dataset) -> xr.Dataset:
    out = ds.copy()
    for name, var in ds.data_vars.items():
        if np.iscomplexobj(var.values):
            parts = np.stack([var.values.real, var.values.imag], axis=-1)
            out[name] = xr.Variable(var.dims + (_PART,), parts, {**var.attrs, _COMPLEX_FLAG: 1})
    if any(_COMPLEX_FLAG in out[v].attrs for v in out.data_vars):
        out = out.assign_coords({_PART: np.array(["real", "imag"])})
    return out


def _join_complex(ds: xr.Dataset) -> xr.Dataset:
    out = ds.copy()
    for name, var in ds.data_vars.items():
        if var.attrs.get(_COMPLEX_FLAG):
            values = var.isel({_PART: 0}).values + 1j * var.isel({_PART: 1}).values
            attrs = {k: v for k, v in var.attrs.items() if k != _COMPLEX_FLAG}
            out[name] = xr.Variable(tuple(d for d in var.dims if d != _PART), values, attrs)
    if _PART in out.dims and not any(_PART in out[v].dims for v in out.data_vars):
        out = out.drop_vars(_PART)
    return out


def save(ds: xr.Dataset, path) -> Path:
    """Write a sweep dataset to ``path`` (netCDF-4 via h5netcdf) atomically: the file
    is written beside the target and renamed, so a crash never leaves half a file."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f"{path.name}.{os.getpid()}.partial")
    try:
        _split_complex(ds).to_netcdf(tmp, engine=_ENGINE)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def load(path) -> xr.Dataset:
    """Read a sweep result file written by :func:`save` (complex variables restored)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"no result file at {path}; run the sweep first (periodyn sweep ... --out {path})")
    try:
        with xr.open_dataset(path, engine=_ENGINE) as raw:
            ds = raw.load()
    except (OSError, ValueError) as exc:
        raise InputError(f"{path} is not a readable periodyn result file ({exc})") from None
    return _join_complex(ds)


def ensure(name: str, results_dir="results", sweeps_dir="sweeps", *, workers: int | str = "auto") -> xr.Dataset:
    """Results of the sweep file ``sweeps/<name>.toml``, from ``<results_dir>/<name>.nc``
    when that file was made from the same sweep file text, else computed and written.

    Relative directories are taken from the project root (the folder holding ``sweeps/``).
    Used by the figure scripts, which only read results and draw.
    """
    from .config import load_sweep_file, project_root  # here: both modules import this one
    from .sweep import sweep_file

    root = project_root()
    spec = load_sweep_file(root / sweeps_dir / f"{name}.toml")
    out = root / results_dir / f"{name}.nc"
    if out.is_file():
        try:
            ds = load(out)
        except InputError:  # unreadable: computed again below
            ds = None
        if ds is not None and ds.attrs.get("sweep_file_text") == spec.text:
            return ds
        out.unlink()  # made from another version of the sweep file: replaced below
    return sweep_file(spec, out=out, workers=workers, resume=True, progress=None)


def options_attrs(options: dict) -> dict:
    """Dataset attributes for sweep options: JSON in ``sweep_options`` plus flat scalars."""
    attrs = {"sweep_options": json.dumps(options, sort_keys=True)}
    for key, value in options.items():
        if isinstance(value, bool):
            attrs[key] = int(value)
        elif isinstance(value, (int, float, str)):
            attrs[key] = value
    return attrs
