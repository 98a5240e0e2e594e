"""Helpers shared by the integration tests: datasets without attributes (xarray >= 2024.1:
``Dataset.drop_attrs`` only exists from 2024.7), a long pendulum sweep file and the SIGINT
setting of a process the tests interrupt."""

import signal

import xarray as xr


def without_attrs(ds: xr.Dataset) -> xr.Dataset:
    """A copy of ds without attributes on the dataset, its variables and coordinates."""
    out = ds.copy()
    out.attrs = {}
    for variable in out.variables.values():
        variable.attrs = {}
    return out


def pendulum_sweep_text(speeds: int, description: str) -> str:
    """A pendulum sweep file of ``speeds`` speeds over 0.05-1.4 omega0 with dense Hill (m = 10,
    48 samples): long enough to be interrupted or lose a worker mid-run."""
    return f"""
description = "{description}"
[model]
example = "pendulum"
[sweep]
omega = {{ start = 0.05, stop = 1.4, num = {speeds}, unit = "omega0" }}
harmonics = 10
samples = 48
stability = "dense"
"""


def sigint_as_in_a_terminal() -> None:
    """``preexec_fn`` of a process the test interrupts with SIGINT: the default action, as
    a foreground command in a terminal has it (a test run started in the background of a
    shell without job control inherits SIGINT ignored, and Python then keeps ignoring it)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
