"""Dataset helpers shared by the integration tests (xarray >= 2024.1: ``Dataset.drop_attrs``
only exists from 2024.7)."""

import xarray as xr


def without_attrs(ds: xr.Dataset) -> xr.Dataset:
    """A copy of ds without attributes on the dataset, its variables and coordinates."""
    out = ds.copy()
    out.attrs = {}
    for variable in out.variables.values():
        variable.attrs = {}
    return out
