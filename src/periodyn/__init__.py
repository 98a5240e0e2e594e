"""periodyn: periodic vibrations, transients and stability of driven mechanisms and rotors.

Data flow: model -> per-sample matrices -> spectra -> harmonic balance / Hill exponents /
averaging transient -> sweep results. See README.md.

The public names below are imported on first use (module ``__getattr__``), so that
``import periodyn`` and the command line start without loading Numba, SciPy, pyFFTW,
xarray or Dask.
"""

from __future__ import annotations

from ._lazy import lazy_package

__version__ = "0.1.0"

#: public name -> module that defines it
_LAZY = {
    "AliasingWarning": "hb", "periodic_solution": "hb", "PeriodicSolution": "periodic",
    "Branch": "continuation", "ContinuationOptions": "continuation", "SpecialPoint": "continuation",
    "continuation": "continuation", "load_branch": "continuation", "switch_branch": "continuation",
    "switch_period_doubling": "continuation", "confirm_special_points": "continuation",
    "ConvergenceError": "errors", "InputError": "errors",
    "DAE": "nonlinear", "ihb": "nonlinear", "PlanarSystem": "model",
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

__all__ = lazy_package(__name__, _LAZY, _SUBMODULES)
