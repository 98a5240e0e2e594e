"""periodyn: periodic vibrations, transients and stability of driven mechanisms and rotors.

Data flow: model -> per-sample matrices -> spectra -> harmonic balance / Hill exponents /
averaging transient -> sweep results. See README.md ("Data flow and layout").

The public names below are imported on first use (module ``__getattr__``), so that
``import periodyn`` and the command line start without loading Numba, SciPy, pyFFTW,
xarray or Dask. No public name is also the name of a submodule.
"""

from __future__ import annotations

import importlib

from . import _moved

__version__ = "0.1.0"

#: public name -> module that defines it, by stage of the data flow
_PUBLIC = {
    # errors
    "InputError": "errors", "ConvergenceError": "errors",
    # problems: linear periodic systems, models, DAEs
    "RheoLinear": "system", "OmegaSplitModel": "system", "PlanarSystem": "model",
    "DAE": "dae", "rheo_linear_dae": "dae", "element_dae": "nonlinear.elements",
    # methods
    "periodic_solution": "harmonic.balance", "AliasingWarning": "harmonic.operator",
    "BalanceTruncationWarning": "harmonic.truncation",
    "characteristic_exponents": "stability.methods", "hill_exponents": "stability.methods",
    "TruncationWarning": "stability.floquet",
    "transient": "averaging", "integrate_stiff": "numerics.stiff",
    "ihb": "nonlinear.ihb_solver", "shooting": "nonlinear.shooting_solver", "element_outputs": "nonlinear.elements",
    "IHBOptions": "nonlinear.options", "ShootingOptions": "nonlinear.options", "IntegrationOptions": "numerics.options",
    "solve_point": "speeds", "campbell": "rotor.diagram", "Unbalance": "rotor.response",
    "unbalance_response": "rotor.response",
    # solutions
    "PeriodicSolution": "periodic", "FloquetExponents": "stability.floquet", "Transient": "averaging",
    "PointResult": "speeds",
    # studies: sweeps, continuation, result files
    "sweep": "engine.front", "ExecutionOptions": "engine.options", "OutputOptions": "engine.options",
    "continuation": "arclength.entry", "ContinuationOptions": "arclength.driver", "Branch": "arclength.branch",
    "Event": "arclength.events", "EventPoint": "arclength.events",
    "SpecialPoint": "arclength.branch", "load_branch": "arclength.branch", "switch_branch": "arclength.switching",
    "switch_period_doubling": "arclength.switching", "confirm_special_points": "arclength.confirm",
    "load": "results", "stability_chart": "stability.charts", "ChartOptions": "stability.chart_data",
    "cardan_shaft": "examples.cardan",
}
_SUBMODULES = ("examples",)
__all__ = sorted([*_PUBLIC, *_SUBMODULES])

_moved.install()


def __getattr__(name: str):
    if name in _PUBLIC:
        value = getattr(importlib.import_module(f".{_PUBLIC[name]}", __name__), name)
    elif name in _SUBMODULES:
        value = importlib.import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
