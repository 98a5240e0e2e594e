"""Continuation results: a columnar ``Branch`` with its special points, saved to netCDF.

File layout (``Branch.to_dataset``; complex values are split into real and imaginary parts
on disk by ``periodyn.results.save``, which also does the file handling):

=====================  ===============================  =======================================
variable               dims                             meaning
=====================  ===============================  =======================================
``omega``              (point,)                         driving frequency, rad/s
``parameter``          (point,)                         continued parameter (omega itself if none)
``amplitude``          (point, coordinate)              half peak-to-peak per coordinate
``stable``             (point,)                         1 stable, 0 unstable, -1 not computed
``max_multiplier``     (point,)                         largest |mu| (nan without stability)
``residual``           (point,)                         corrector residual max-norm
``iterations``         (point,)                         corrector Newton updates
``defect``             (point,)                         orbit defect (IHB; absent if not computed)
``harmonics``          (point, harmonic, coordinate)    complex q harmonics, l = -m..m
``lambda_harmonics``   (point, harmonic, constraint)    complex constraint-force harmonics
``multipliers``        (point, multiplier)              complex Floquet multipliers (nan if none)
``special_*``          (special, ...)                   type, index, omega, parameter, critical
                                                        multiplier, amplitude, multipliers, test
                                                        values, critical eigenvector (unknown),
                                                        the orbit's harmonics there, confirmed
                                                        (1, 0, -1 unchecked), check (reason)
                                                        and defect (orbit defect)
``special_unknowns``   (special, unknown)               the discretization's unknowns at the
                                                        refined point (nan if not refined)
``problem_references`` (reference, coordinate)          shooting only: the configurations at
                                                        which the problem chose its independent
                                                        coordinates (those of the unknowns)
=====================  ===============================  =======================================

Attributes: parameter_name ('' for omega), status, method, subharmonic, options (JSON).
Loaded, the special unknowns and references are ``options["special_unknowns"]`` and
``options["problem_references"]``: with the options they rebuild the problem, so that a
loaded branch can be switched from (``switch_branch(..., system=)``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import xarray as xr

from ..stability.floquet import FloquetExponents
from ..periodic import PeriodicSolution
from ..results import load, save

__all__ = ["SpecialPoint", "Branch", "load_branch"]


@dataclass(frozen=True, eq=False)
class SpecialPoint:
    """A bifurcation between branch points ``index`` and ``index + 1``.

    type: "fold", "branch-point", "period-doubling", "neimark-sacker" (``events.SPECIAL_POINTS``)
    or the name of a user ``Event``; omega (rad/s) and
    parameter at the refined location (linear interpolation when refinement failed);
    multiplier: the critical multiplier (nan for folds); amplitude (n,) half peak-to-peak
    there; solution: the orbit there (None when refinement failed); multipliers: its
    Floquet multipliers; eigenvector (N,): the critical direction of a fold or branch point,
    the unit null vector of the discretization's Jacobian in its unknowns (None otherwise
    or when refinement failed); test_values (3,): the test function at the bracketing
    branch points and at the located point (dp/ds for folds, sign(det(M - I)) min|mu - 1|
    for branch points, |mu| - 1 of the multiplier of the crossing kind nearest the unit circle
    for the other built-in points, the event's test for a user event; None when refinement
    failed); confirmed: the
    verdict of ``check_truncation`` / ``confirm_special_points`` (None when not checked or
    not decided), check: its reason; defect: the orbit defect there (``orbit_defect``,
    dimensionless; nan when not checked).
    """

    type: str
    index: int
    omega: float
    parameter: float
    multiplier: complex = complex("nan")
    amplitude: np.ndarray | None = None
    solution: PeriodicSolution | None = None
    eigenvector: np.ndarray | None = None
    test_values: np.ndarray | None = None
    confirmed: bool | None = None
    check: str = ""
    defect: float = float("nan")

    @property
    def multipliers(self) -> np.ndarray | None:
        return None if self.solution is None else self.solution.multipliers


@dataclass(frozen=True, eq=False)
class Branch:
    """Columnar continuation result (k points).

    omega (k,) rad/s; parameter (k,) values of the continued parameter (== omega for
    omega continuation); parameter_name (None for omega); amplitude (k, n); stable (k,)
    bool (object array with None entries without stability); max_multiplier (k,);
    residual (k,) and iterations (k,) of each corrector; special_points; solutions: the
    PeriodicSolution of every point; status: why the branch ended; problem and options:
    what produced it (problem is None for a branch loaded from a file); unknowns (k, N):
    the discretization's unknowns (None when loaded); defect (k,): the orbit defect of each
    point (``truncation.branch_defects``, dimensionless; None when not computed).
    """

    omega: np.ndarray
    parameter: np.ndarray
    parameter_name: str | None
    amplitude: np.ndarray
    stable: np.ndarray
    max_multiplier: np.ndarray
    residual: np.ndarray
    iterations: np.ndarray
    special_points: tuple[SpecialPoint, ...]
    solutions: tuple
    status: str
    problem: Any = field(repr=False, default=None)
    options: dict = field(default_factory=dict)
    unknowns: np.ndarray | None = field(repr=False, default=None)
    defect: np.ndarray | None = field(repr=False, default=None)

    def __len__(self) -> int:
        return len(self.omega)

    def points(self, type: str) -> list[SpecialPoint]:
        """Special points of one type."""
        return [s for s in self.special_points if s.type == type]

    @classmethod
    def from_solutions(cls, solutions, parameter, parameter_name, special_points, status, problem=None,
                       options=None, unknowns=None, amplitude=None) -> "Branch":
        """Columns from the PeriodicSolutions of the points (amplitude computed unless given)."""
        stable = [s.stable for s in solutions]
        amplitude = np.array([s.amplitude() for s in solutions]) if amplitude is None else amplitude
        return cls(np.array([s.omega for s in solutions]), np.asarray(parameter, float), parameter_name, amplitude,
                   np.array(stable, dtype=object if any(v is None for v in stable) else bool),
                   np.array([s.max_multiplier for s in solutions]), np.array([s.residual for s in solutions]),
                   np.array([s.iterations for s in solutions]), tuple(special_points), tuple(solutions), status,
                   problem, dict(options or {}), unknowns)

    # ------------------------------------------------------------------ netCDF
    def to_dataset(self) -> xr.Dataset:
        """The branch as an xarray Dataset (module docstring)."""
        sols = list(self.solutions)
        s0 = sols[0]
        sps = list(self.special_points)
        ds = xr.Dataset(
            {"omega": ("point", self.omega), "parameter": ("point", self.parameter),
             "amplitude": (("point", "coordinate"), self.amplitude),
             "stable": ("point", np.array([-1 if v is None else int(v) for v in self.stable], np.int8)),
             "max_multiplier": ("point", self.max_multiplier), "residual": ("point", self.residual),
             "iterations": ("point", self.iterations.astype(np.int64)),
             "harmonics": (("point", "harmonic", "coordinate"), np.stack([s.harmonics for s in sols])),
             "lambda_harmonics": (("point", "harmonic", "constraint"), np.stack([_lam(s) for s in sols])),
             "multipliers": (("point", "multiplier"), _multipliers([s for s in sols])),
             "special_type": ("special", np.array([p.type for p in sps], dtype=str)),
             "special_index": ("special", np.array([p.index for p in sps], np.int64)),
             "special_omega": ("special", np.array([p.omega for p in sps], float)),
             "special_parameter": ("special", np.array([p.parameter for p in sps], float)),
             "special_multiplier": ("special", np.array([p.multiplier for p in sps], complex)),
             "special_amplitude": (("special", "coordinate"), _rows([p.amplitude for p in sps], s0.harmonics.shape[1])),
             "special_multipliers": (("special", "multiplier"), _multipliers([p.solution for p in sps],
                                                                             len(_multipliers(sols)[0]))),
             "special_test_values": (("special", "test"), _rows([p.test_values for p in sps], 3)),
             **self._unknown_variables(),
             "special_harmonics": (("special", "harmonic", "coordinate"),
                                   _stack([p.solution and p.solution.harmonics for p in sps], s0.harmonics.shape)),
             "special_lambda_harmonics": (("special", "harmonic", "constraint"),
                                          _stack([p.solution and _lam(p.solution) for p in sps], _lam(s0).shape)),
             "special_confirmed": ("special", np.array([-1 if p.confirmed is None else int(p.confirmed) for p in sps],
                                                       np.int8)),
             "special_check": ("special", np.array([p.check for p in sps], dtype=str)),
             "special_defect": ("special", np.array([p.defect for p in sps], float))},
            coords={"harmonic": np.arange(-s0.m, s0.m + 1), "coordinate": list(s0.coordinate_names),
                    "constraint": list(s0.constraint_names)})
        if self.defect is not None:
            ds["defect"] = ("point", np.asarray(self.defect, float))
        opts = {k: v for k, v in self.options.items() if isinstance(v, (int, float, str, bool, type(None)))}
        ds.attrs.update(parameter_name=self.parameter_name or "", status=self.status, method=s0.method,
                        subharmonic=int(s0.subharmonic), options=json.dumps(opts, sort_keys=True),
                        stability_method=_stability_method(sols))
        return ds

    def _unknown_variables(self) -> dict:
        """Variables in the discretization's unknowns: the special points' critical vectors
        and refined unknowns, and a shooting problem's references (module docstring)."""
        vectors = [p.eigenvector for p in self.special_points]
        unknowns = list(self.options.get("special_unknowns", ())) or [None] * len(vectors)
        width = _width(vectors + unknowns)
        out = {"special_eigenvector": (("special", "unknown"), _rows(vectors, width)),
               "special_unknowns": (("special", "unknown"), _rows(unknowns, width))}
        references = getattr(self.problem, "refs", self.options.get("problem_references"))
        if references is not None:
            out["problem_references"] = (("reference", "coordinate"), np.asarray(references, float))
        return out

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> "Branch":
        """A Branch from :meth:`to_dataset` output (the problem and the points' unknowns are not
        stored; the special points' unknowns are, in ``options``)."""
        nu, method = int(ds.attrs["subharmonic"]), str(ds.attrs["method"])
        smethod = ds.attrs.get("stability_method", "")
        names = tuple(str(c) for c in ds["coordinate"].values)
        cnames = tuple(str(c) for c in ds["constraint"].values)
        name = ds.attrs["parameter_name"] or None

        def solution(omega, h, lam, mu, residual, iterations, parameter):
            stab = None if np.all(np.isnan(mu)) else FloquetExponents.from_multipliers(mu, omega, smethod, nu)
            params = {} if name is None else {name: float(parameter)}
            return PeriodicSolution(float(omega), h, None, names, names, float(residual), iterations=int(iterations),
                                    method=method, subharmonic=nu, lambda_harmonics=lam, constraint_names=cnames,
                                    stability=stab, parameters=params)

        v = {k: ds[k].values for k in ds.data_vars}
        sols = [solution(*args) for args in zip(v["omega"], v["harmonics"], v["lambda_harmonics"], v["multipliers"],
                                                v["residual"], v["iterations"], v["parameter"])]
        specials = []
        for j in range(ds.sizes["special"]):
            h = v["special_harmonics"][j]
            sol = None if np.all(np.isnan(h)) else solution(v["special_omega"][j], h, v["special_lambda_harmonics"][j],
                                                             v["special_multipliers"][j], np.nan, 0,
                                                             v["special_parameter"][j])
            specials.append(SpecialPoint(str(v["special_type"][j]), int(v["special_index"][j]),
                                         float(v["special_omega"][j]), float(v["special_parameter"][j]),
                                         complex(v["special_multiplier"][j]), v["special_amplitude"][j], sol,
                                         _row(v, "special_eigenvector", j), _row(v, "special_test_values", j),
                                         *_verdict(v, j)))
        options = json.loads(ds.attrs["options"])
        if "special_unknowns" in v:
            options["special_unknowns"] = tuple(_row(v, "special_unknowns", j) for j in range(ds.sizes["special"]))
        if "problem_references" in v:
            options["problem_references"] = v["problem_references"]
        branch = cls.from_solutions(sols, v["parameter"], name, specials, str(ds.attrs["status"]),
                                    options=options, amplitude=v["amplitude"])
        return replace(branch, max_multiplier=v["max_multiplier"],  # as stored, not exp(log(mu))
                       defect=v.get("defect"))

    def save(self, path):
        """Write the branch to a netCDF file (``periodyn.results.save``); returns the path."""
        return save(self.to_dataset(), path)


def load_branch(path) -> Branch:
    """Read a branch written by :meth:`Branch.save`."""
    return Branch.from_dataset(load(path))


def _verdict(v: dict, j: int) -> tuple:
    """(confirmed, check, defect) of special point j; (None, "", nan) in files written before the check."""
    if "special_confirmed" not in v:
        return None, "", np.nan
    c = int(v["special_confirmed"][j])
    defect = float(v["special_defect"][j]) if "special_defect" in v else np.nan
    return (None if c < 0 else bool(c)), str(v["special_check"][j]), defect


def _lam(sol) -> np.ndarray:
    return sol.lambda_harmonics if sol.lambda_harmonics is not None else np.zeros((sol.harmonics.shape[0], 0), complex)


def _stability_method(sols) -> str:
    return next((s.stability.method for s in sols if s.stability is not None), "")


def _multipliers(sols, width: int | None = None) -> np.ndarray:
    """(k, width) complex multipliers, nan where a solution has none."""
    mus = [None if s is None else s.multipliers for s in sols]
    if width is None:
        width = max((len(m) for m in mus if m is not None), default=0)
    out = np.full((len(sols), width), np.nan + 0j)
    for i, m in enumerate(mus):
        if m is not None:
            out[i, :len(m)] = m
    return out


def _width(rows) -> int:
    return max((len(r) for r in rows if r is not None), default=0)


def _row(v: dict, name: str, j: int) -> np.ndarray | None:
    """Row j of a stored special-point variable; None when absent (older files) or all nan."""
    if name not in v or v[name].shape[1] == 0 or np.all(np.isnan(v[name][j])):
        return None
    return v[name][j]


def _rows(rows, n) -> np.ndarray:
    out = np.full((len(rows), n), np.nan)
    for i, r in enumerate(rows):
        if r is not None:
            out[i] = r
    return out


def _stack(arrays, shape) -> np.ndarray:
    out = np.full((len(arrays),) + tuple(shape), np.nan + 0j)
    for i, a in enumerate(arrays):
        if a is not None:
            out[i] = a
    return out
