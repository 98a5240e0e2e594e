"""periodyn: periodic vibrations, transients and stability of driven mechanisms and rotors.

Data flow: model -> per-sample matrices -> spectra -> harmonic balance / Hill exponents /
averaging transient -> sweep results. See README.md.

The public names below are imported on first use (module ``__getattr__``), so that
``import periodyn`` and the command line start without loading Numba, SciPy, pyFFTW,
xarray or Dask.
"""

from __future__ import annotations

import importlib
import sys
import types

__version__ = "0.1.0"

#: public name -> module that defines it
_LAZY = {
    "AliasingWarning": "hb", "periodic_solution": "hb", "PeriodicSolution": "periodic",
    "Branch": "continuation", "ContinuationOptions": "continuation", "SpecialPoint": "continuation",
    "continuation": "continuation", "load_branch": "continuation", "switch_branch": "continuation",
    "switch_period_doubling": "continuation", "confirm_special_points": "continuation",
    "ConvergenceError": "errors", "InputError": "errors",
    "DAE": "dae", "ihb": "dae",
    "FloquetExponents": "floquet", "characteristic_exponents": "hill", "hill_exponents": "hill",
    "PointResult": "analysis", "solve_point": "analysis",
    "shooting": "nonlinear", "element_dae": "nonlinear", "element_outputs": "nonlinear",
    "integrate_stiff": "nonlinear", "rheo_linear_dae": "nonlinear",
    "load": "results",
    "campbell": "rotor",
    "cardan_shaft": "examples",
    "sweep": "sweep",
    "OmegaSplitModel": "system", "RheoLinear": "system",
    "Transient": "transient", "transient": "transient",
}
_SUBMODULES = ("examples",)

__all__ = sorted([*_LAZY, *_SUBMODULES])


def __getattr__(name: str):
    if name in _LAZY:
        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    elif name in _SUBMODULES:
        value = importlib.import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module 'periodyn' has no attribute {name!r}")
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])


class _Package(types.ModuleType):
    """The package module: importing a submodule named like the function it defines
    (sweep, transient, continuation) must not replace that function by the submodule;
    the submodule stays reachable as ``sys.modules["periodyn.<name>"]``."""

    def __setattr__(self, name: str, value) -> None:
        if _LAZY.get(name) == name and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
