"""The stability methods: ONE registry ``{name: StabilityMethod}``, the rule of "auto" and
its costs, and the scalar entry points that dispatch through it.

Vocabulary (:func:`names`): "dense" and "sparse" (Hill's method, :mod:`.hill`), "hill"
(whichever of the two is estimated cheaper, :func:`choose_method`), "magnus" (fixed-step
4th-order Magnus monodromy, :mod:`.magnus`), "monodromy" (DOP853 reference, :mod:`.monodromy`)
and "auto": the certified Magnus ladder where its error estimate settles the verdict within
HILL_TIME_FACTOR times the estimated cost of "hill", else "hill" (:func:`auto_exponents`; a
small unconstrained orbit: the Magnus flow of its samples, :func:`flow_choice`);
"reduced": the ladder on a mean-system modal reduction with a certified Schur correction
(:mod:`.reduced`; what it does not certify goes to "auto"), which a sweep's "auto" takes first
on element models where it is estimated cheaper (:func:`.reduced.reduced_costs`).
Sweeps (:class:`periodyn.stability.batch.SpeedStability`), :func:`characteristic_exponents`,
orbits (:func:`periodyn.nonlinear.orbit_linearization.orbit_exponents`) and boundaries all
look their method up here. A new method is one module plus one :func:`register` call.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Callable

import numpy as np

from ..errors import ConvergenceError, InputError
from ..harmonic.operator import HarmonicOperator, HillOperator, check_harmonics
from ..harmonic.pattern import BlockPattern
from ..system import RheoLinear
from .floquet import STABILITY_TOL, TRUNCATION_TOL, FloquetExponents, TruncationWarning, truncation_message
from .hill import arpack_k, hill_solve, shift_frequencies, shift_grid, top_frequencies
from .magnus import MagnusLadder, sweep_exponents, sweep_terms
from .monodromy import monodromy_exponents
from .reduced import ReducedStability, reduced_choices, reduced_costs, reduced_first, system_model

__all__ = ["StabilityMethod", "register", "method_named", "check_method", "names", "characteristic_exponents",
           "operator_exponents", "hill_exponents", "spectra_operator", "auto_exponents", "choose_method",
           "method_costs", "flow_choice", "hill_cost", "hill_costs_many", "magnus_reason", "stability_choice",
           "HILL_TIME_FACTOR", "DeferredOperator"]


@dataclass(frozen=True)
class StabilityMethod:
    """One entry of the registry.

    name, description: its key and one line on what it computes.
    exponents(system, operator, steps=None) -> FloquetExponents at one speed: ``system`` the
    RheoLinear (None unless ``system``), ``operator`` its HillOperator (None unless
    ``operator``), ``steps`` fixed Magnus steps per period (None: the method's default).
    choose(stage, w) -> (names (S,), reasons (S,), exponents (S, 2n), solved (S,)[, records]):
    a method that hands each speed w (S,) rad/s to another one (``delegates``) or solves it
    itself; ``records`` ({column: (S,) values}, optional) are per-speed columns of the
    results (:data:`periodyn.results.STABILITY_RECORDS`).
    prepare(model) -> per-model data kept by a sweep (``stage.prepared(name)``).
    batch(stage, w) -> (exponents (S, 2n), messages (S,)[, Hill truncation indicators (S,)]):
    a chunk of speeds at once.
    sweep_cost(stage, w, base) -> estimated seconds (S,) of a speed whose harmonic balance
    costs ``base`` s. cost(pattern, n, shifts) -> estimated seconds at one speed (the Hill
    methods, compared by the auto rule). rule: how it chooses per point, recorded with a sweep.
    deferred: ``exponents`` accepts a :class:`DeferredOperator` (builds the operator only when needed).
    """

    name: str
    description: str
    exponents: Callable[..., FloquetExponents]
    operator: bool = False
    system: bool = False
    choose: Callable | None = None
    delegates: tuple[str, ...] = ()
    prepare: Callable | None = None
    batch: Callable | None = None
    sweep_cost: Callable | None = None
    cost: Callable | None = None
    rule: str = ""
    deferred: bool = False


REGISTRY: dict[str, StabilityMethod] = {}


def register(method: StabilityMethod) -> StabilityMethod:
    """Add ``method`` to the registry under its name (a name taken raises InputError)."""
    if not isinstance(method, StabilityMethod):
        raise InputError(f"register takes a periodyn.stability.methods.StabilityMethod, got {type(method).__name__}")
    if method.name in REGISTRY:
        raise InputError(f"a stability method named {method.name!r} is registered already")
    REGISTRY[method.name] = method
    return method


def names() -> tuple[str, ...]:
    """The registered stability method names, in registration order."""
    return tuple(REGISTRY)


def method_named(name: str) -> StabilityMethod:
    """The registry entry of ``name``; InputError naming the choices when there is none."""
    method = REGISTRY.get(name) if isinstance(name, str) else None
    if method is None:
        raise InputError(f"unknown method {name!r} (no stability method of that name); choose one of {names()}")
    return method


def check_method(name: str) -> str:
    """``name`` when it is a registered stability method, else InputError."""
    return method_named(name).name


def stability_choice(stability, method: str | None = None, where: str = "sweep") -> tuple[bool, str]:
    """(compute stability?, method name) from ``stability=`` (True = "auto", False, or a
    method name) and the deprecated ``method=`` of ``where`` (warns; the old meaning kept)."""
    if method is not None:
        warnings.warn(f"{where}(method=...) is deprecated and goes in the next release; pass "
                      f"stability={method!r} (True, False or the stability method's name)", DeprecationWarning,
                      stacklevel=3)
        if isinstance(stability, str) and stability != method:
            raise InputError(f"stability={stability!r} and method={method!r} disagree; pass only stability=")
    if isinstance(stability, str):
        return True, check_method(stability)
    if not isinstance(stability, (bool, np.bool_)):
        raise InputError(f"stability must be True, False or a stability method's name {names()}, got {stability!r}")
    return bool(stability), check_method("auto" if method is None else method)


# Cost model of the two Hill methods, seconds on one core (fitted on the parametric chain
# and the slider-crank, m = 4..30): dense, real dgeev of size D = 2N plus the cluster
# selection; sparse, per ARPACK shift one LU of the band and the Arnoldi work on ncv vectors.
_DENSE_COST = (1.0e-9, 1.0e-4)  # s per D^3, s per call
_SHIFT_COST = (6.0e-10, 5.0e-3)  # s per flop-like unit, s per shift (ARPACK set-up)
#: Measured time of the dense Hill path (eigenvectors, basis change, cluster selection) over
#: its estimate _DENSE_COST, which counts the eigen-solve: 5-20x on the pendulum (D = 18-130)
#: and about 14x on the slider-crank (D = 200); Magnus may spend this multiple of Hill's estimate.
HILL_TIME_FACTOR = 4.0
# sweep costs (load balance): the Magnus climb over its first comparison (Cardan shaft:
# 6.6-10.7x measured over 0-1 omega_b); DOP853 over one period at the sweep's highest speed
_CLIMB_FACTOR = 8.0
_MONODROMY_SECONDS = 1e-3
_ORBIT_SETUP = 1.0e-3  # s of the linearized-orbit path before its first Magnus rung (1-DOF, H = 7)


@lru_cache(maxsize=256)
def _costs(N: int, u: int, n: int) -> tuple[float, float, str]:
    """Estimated seconds of dense Hill and of one ARPACK shift, and the reason for dense
    when it is cheaper than one shift (N = (2m+1)n, half bandwidth u)."""
    ncv = 2 * arpack_k(N, n) + 1
    dense = _DENSE_COST[0] * (2 * N) ** 3 + _DENSE_COST[1]
    per_shift = _SHIFT_COST[1] + _SHIFT_COST[0] * (N * u * u + 8 * N * ncv * ncv + 10 * ncv * N * u)
    return dense, per_shift, f"estimated dense {dense:.2g} s <= one ARPACK shift {per_shift:.2g} s (size {2 * N}, band {u})"


def method_costs(pattern: BlockPattern) -> tuple[float, float]:
    """Estimated seconds of dense Hill and of one sparse (ARPACK) shift on ``pattern``."""
    return _costs(pattern.size, pattern.half_bandwidth, pattern.n)[:2]


def flow_choice(rho: float) -> tuple[bool, str]:
    """Whether "auto" takes the Magnus flow of an unconstrained orbit's samples (:mod:`.orbit_flow`), and why: when
    its generator over a period, rho = max ||A|| T, is within the ladder's first rung (FIRST_RHO x START[6]), both
    climb the same rungs and the flow saves the linearized orbit's set-up (~_ORBIT_SETUP s); stiffer goes there."""
    limit = MagnusLadder.FIRST_RHO * MagnusLadder.START[6]
    return rho <= limit, f"Magnus flow of the orbit's samples (generator {rho:.3g} <= {limit:g} per period)"


def choose_method(op: HillOperator) -> tuple[str, str]:
    """The Hill method ("dense" or "sparse") "hill" takes at this operator, and why: the
    cheaper by estimated cost of dense (all eigenvalues, ~D^3 for D = 2N) and sparse (one
    shift-invert ARPACK run per shift; the shifts cover the mean system's frequencies in
    steps of m omega / 2, so a stiff system with few harmonics needs many)."""
    method, _, reason = hill_cost(op)
    return method, reason


def hill_cost(op: HillOperator) -> tuple[str, float, str]:
    """:func:`choose_method` with the estimated seconds of the chosen Hill method."""
    pat = op.pattern
    dense, per_shift, _ = _costs(pat.size, pat.half_bandwidth, op.n)
    return _hill_choice(pat, op.n, 0 if dense <= per_shift else shift_frequencies(op).size)


def hill_costs_many(harmonic: HarmonicOperator, omegas: np.ndarray) -> list[tuple[str, float, str]]:
    """:func:`hill_cost` at speeds (S,) rad/s from the omega-polynomial operator, without
    evaluating the whole operator per speed: the shift count needs only its mean block."""
    pat, n = harmonic.pattern, harmonic.n
    dense, per_shift, _ = _costs(pat.size, pat.half_bandwidth, n)
    if dense <= per_shift:
        return [_hill_choice(pat, n, 0)] * len(omegas)
    W0, V0, M0 = harmonic.mean_blocks_many(omegas)
    tops = top_frequencies(W0, V0, M0)
    return [_hill_choice(pat, n, shift_grid(top, w, pat.m).size) for top, w in zip(tops, omegas)]


def _hill_choice(pat: BlockPattern, n: int, shifts: int) -> tuple[str, float, str]:
    """The cheaper Hill method by the registry's costs, its estimated seconds and why, with
    ``shifts`` ARPACK shifts for sparse (0: dense costs less than one shift)."""
    dense = REGISTRY["dense"].cost(pat, n, shifts)
    if shifts == 0:
        return "dense", dense, _costs(pat.size, pat.half_bandwidth, n)[2]
    sparse = REGISTRY["sparse"].cost(pat, n, shifts)
    size = f"size {2 * pat.size}, band {pat.half_bandwidth}"
    return ("dense" if dense <= sparse else "sparse", min(dense, sparse),
            f"estimated dense {dense:.2g} s vs sparse {sparse:.2g} s ({shifts} shifts, {size})")


def magnus_reason(est, i: int, hill: str, hill_seconds: float, first_cost: float) -> str:
    """Why "auto" took Magnus or Hill at speed i of a :class:`MagnusEstimate`."""
    if est.accepted[i]:
        return (f"Magnus of order {est.order[i]} with {est.steps[i]} steps: estimated error {est.error[i]:.1g} "
                f"(tolerance {STABILITY_TOL:g}) and verdict margin {est.margin[i]:.2g}; estimated {first_cost:.2g} s vs {hill} Hill "
                f"{hill_seconds:.2g} s")
    if est.steps[i] == 0:
        return f"{hill} Hill: estimated {hill_seconds:.2g} s <= Magnus {first_cost:.2g} s"
    return (f"{hill} Hill: the Magnus estimate did not certify the verdict within {HILL_TIME_FACTOR:g} x "
            f"{hill_seconds:.2g} s ({est.steps[i]} steps: error {est.error[i]:.1g}, margin {est.margin[i]:.2g})")


@dataclass(frozen=True)
class DeferredOperator:
    """A Hill operator built only when called: ``build()`` -> HillOperator of m harmonics
    and n coordinates (what "auto" needs to size Hill's cost before it exists)."""

    m: int
    n: int
    build: Callable[[], HillOperator]

    def __call__(self) -> HillOperator:
        return self.build()


def auto_exponents(system: RheoLinear, op, steps: int | None = None) -> FloquetExponents:
    """Stability method "auto" at one system: Magnus with step doubling where its error
    estimate certifies the verdict within the estimated cost of the cheaper Hill method
    (:class:`periodyn.stability.magnus.MagnusLadder`), else that Hill method; the choice and
    its reason are on the result (the rule of the sweeps, which build the ladder once per
    model). op: the HillOperator, or a :class:`DeferredOperator`: then the ladder is first
    given the least either Hill method can cost at its size (dense, or one ARPACK shift on
    the narrowest band), and the operator is built only when that does not settle the
    verdict (a small orbit's Magnus run costs far less than building it). steps: unused."""
    S = system.spectra
    ladder = MagnusLadder(S.mass, S.damping[..., None], S.stiffness[..., None])
    w = np.array([float(system.omega)])
    if isinstance(op, DeferredOperator):
        floor = min(_costs((2 * op.m + 1) * op.n, op.n, op.n)[:2])
        est = ladder.solve(w, np.array([floor * HILL_TIME_FACTOR]))
        if est.accepted[0]:
            return _magnus_result(system, est, magnus_reason(est, 0, "least", floor, float(est.first_cost[0])))
        op = op()
    hill, seconds, _ = hill_cost(op)
    est = ladder.solve(w, np.array([seconds * HILL_TIME_FACTOR]))
    reason = magnus_reason(est, 0, hill, seconds, float(est.first_cost[0]))
    return _magnus_result(system, est, reason) if est.accepted[0] else hill_solve(op, hill, reason)


def _magnus_result(system: RheoLinear, est, reason: str) -> FloquetExponents:
    nan = np.full(2 * system.n, np.nan)
    return FloquetExponents(float(system.omega), est.exponents[0], nan, nan.copy(), "magnus", reason=reason)


def _hill_choices(stage, w: np.ndarray):
    """"hill" per speed in a sweep: the cheaper Hill method, left to it to solve."""
    names, reasons, _ = zip(*stage.hill_choices(w))
    return (np.array(names, dtype=object), np.array(reasons, dtype=object), np.full((w.size, 2 * stage.n), np.nan + 0j),
            np.zeros(w.size, dtype=bool))


def _full_auto(stage, w: np.ndarray):
    """"auto" per speed in a sweep on the full model (the speeds the reduced method does not
    take, :func:`periodyn.stability.reduced.reduced_first`): its Magnus ladder solves where
    it certifies, else Hill."""
    hill = stage.hill_choices(w)
    seconds = np.array([c for _, _, c in hill])
    est = stage.prepared("auto").solve(w, seconds * HILL_TIME_FACTOR)
    names = np.array(["magnus" if ok else h for ok, (h, _, _) in zip(est.accepted, hill)], dtype=object)
    reasons = np.array([magnus_reason(est, i, hill[i][0], seconds[i], est.first_cost[i]) for i in range(w.size)],
                       dtype=object)
    exps = np.full((w.size, 2 * stage.n), np.nan + 0j)
    exps[est.accepted] = est.exponents[est.accepted]
    return names, reasons, exps, est.accepted


def _auto_cost(stage, w: np.ndarray, base: float) -> np.ndarray:
    """The reduced method's estimate where "auto" takes it, else the Magnus climb (_CLIMB_FACTOR
    times the ladder's first comparison), at most what the budget rule lets it spend before Hill."""
    reduced = reduced_costs(stage, w)  # where "auto" takes the reduced method (inf elsewhere)
    if np.isfinite(reduced).all():
        return base + reduced
    hill = np.array([c for _, _, c in stage.hill_choices(w)])
    climb = np.minimum(_CLIMB_FACTOR * stage.prepared("auto").first_cost(w), HILL_TIME_FACTOR * hill)
    return base + np.where(np.isfinite(reduced), reduced, climb + np.where(climb >= HILL_TIME_FACTOR * hill, hill, 0.0))


def _reduced_exponents(system: RheoLinear, op: HillOperator, steps=None) -> FloquetExponents:
    """Stability method "reduced" at one system (its own mean modes, m from the operator);
    a speed it does not certify goes to "auto" on the full system."""
    w = np.array([float(system.omega)])
    exps, done, reasons, _ = ReducedStability(system_model(system)).solve(w, op.m)
    if not done[0]:
        fl = auto_exponents(system, op)
        return replace(fl, reason=f"{reasons[0]}; {fl.reason}")
    nan = np.full(2 * system.n, np.nan)
    return FloquetExponents(float(system.omega), exps[0], nan, nan.copy(), "reduced", reason=reasons[0])


def _hill_rule(choice: str) -> Callable[..., FloquetExponents]:
    """Scalar entry of a Hill method ("hill": the cheaper one by :func:`choose_method`)."""
    def exponents(system, op: HillOperator, steps=None) -> FloquetExponents:
        return hill_solve(op, *choose_method(op)) if choice == "hill" else hill_solve(op, choice)
    return exponents


_HILL_RULE = "dense or sparse Hill, whichever is estimated cheaper (per point: variable stability_method)"
_AUTO_RULE = ("auto: on element models where it is estimated cheaper the method reduced, then "
              "Magnus monodromy with step doubling where its error estimate (Richardson, N vs N/2 steps) is "
              "below the stability tolerance and the verdict cannot flip, at less than the estimated cost of Hill; "
              f"else {_HILL_RULE}")
for _method in (
        StabilityMethod("auto", "certified Magnus ladder where it settles the verdict within Hill's estimated cost, "
                                "else the cheaper Hill method",
                        auto_exponents, operator=True, system=True, delegates=("dense", "sparse"),
                        choose=lambda stage, w: reduced_first(stage, w, _full_auto),
                        prepare=lambda model: MagnusLadder(*model._power_spectra[:3]), sweep_cost=_auto_cost,
                        rule=_AUTO_RULE, deferred=True),
        StabilityMethod("sparse", "Hill's method, ARPACK shift-invert subset of the eigenvalues",
                        _hill_rule("sparse"), operator=True,
                        cost=lambda pat, n, shifts: shifts * _costs(pat.size, pat.half_bandwidth, n)[1]),
        StabilityMethod("dense", "Hill's method, all eigenvalues (LAPACK; stacked over a chunk of speeds)",
                        _hill_rule("dense"), operator=True, batch=lambda stage, w: stage.dense_batch(w),
                        cost=lambda pat, n, shifts: _costs(pat.size, pat.half_bandwidth, n)[0]),
        StabilityMethod("monodromy", "monodromy matrix by adaptive DOP853 integration over one period (reference)",
                        lambda system, op, steps=None: monodromy_exponents(system, "monodromy"), system=True,
                        sweep_cost=lambda stage, w, base: base + _MONODROMY_SECONDS * w.max() / w),
        StabilityMethod("magnus", "fixed-step 4th-order Magnus monodromy",
                        lambda system, op, steps=None: monodromy_exponents(system, "magnus", steps), system=True,
                        prepare=sweep_terms,
                        batch=lambda stage, w: sweep_exponents(stage.prepared("magnus"), w, stage.n)),
        StabilityMethod("hill", "dense or sparse Hill, whichever is estimated cheaper", _hill_rule("hill"),
                        operator=True, choose=_hill_choices, delegates=("dense", "sparse"),
                        rule=f"hill: {_HILL_RULE}"),
        StabilityMethod("reduced", "certified Magnus ladder on the mean-system modal reduction with a "
                                   "Schur-complement correction for the modes left out, else auto",
                        _reduced_exponents, operator=True, system=True, choose=reduced_choices,
                        delegates=("auto", "dense", "sparse"), prepare=ReducedStability,
                        rule="reduced: the ladder on k mean-system modes plus the Schur correction, certified by "
                             "ladder error + 2 |d_lambda| T; k doubled where not certified, else auto")):
    register(_method)


def operator_exponents(op: HillOperator, method: str = "auto") -> FloquetExponents:
    """Exponents from a Hill operator by a method that needs only it ("auto" on an
    operator alone means "hill": the cheaper Hill method)."""
    entry = method_named("hill" if method == "auto" else method)
    if entry.system:
        raise InputError(f"stability method {entry.name!r} needs the system; use characteristic_exponents(system, "
                         f"harmonics, method={entry.name!r})")
    return entry.exponents(None, op)


def spectra_operator(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, omega: float,
                     harmonics: int) -> HillOperator:
    """The unforced Hill operator at omega (rad/s) with m = harmonics from coefficient
    spectra (2K+1, n, n) of M, C, K."""
    m = check_harmonics(harmonics)
    force = np.zeros((mass.shape[0], mass.shape[1], 1))
    return HarmonicOperator.from_power_spectra(mass, damping[..., None], stiffness[..., None], force, m).at(omega)


def hill_exponents(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, omega: float,
                   harmonics: int, method: str = "auto") -> FloquetExponents:
    """Exponents of ``M(t) y'' + C(t) y' + K(t) y = 0`` from coefficient spectra.

    mass, damping, stiffness: two-sided spectra (2K+1, n, n); omega: rad/s; harmonics: m.
    method: "auto" or "hill" (the cheaper of the two by estimated cost, :func:`choose_method`),
    "sparse", "dense", or another registered method that needs only the Hill operator.
    """
    if method_named(method).system and method != "auto":
        check_harmonics(harmonics)
        raise InputError(f"hill_exponents works on spectra; use characteristic_exponents(system, m, method={method!r})")
    return operator_exponents(spectra_operator(mass, damping, stiffness, omega, harmonics), method)


def characteristic_exponents(system: RheoLinear, harmonics: int, method: str = "auto", *,
                             form: str = "direct", truncation: str = "refuse") -> FloquetExponents:
    """Characteristic exponents of the homogeneous rheo-linear system.

    method: a registered stability method (:func:`names`): "sparse" (ARPACK shift-invert
    subset), "dense" (all Hill eigenvalues), "hill" (the cheaper of the two), "monodromy"
    (adaptive integration over one period, the reference), "magnus" (fixed-step 4th-order
    Magnus monodromy, fast for small stiff systems), "auto" (Magnus with step doubling where
    its error estimate certifies the verdict at less than the estimated cost of Hill, else
    dense or sparse Hill, whichever is estimated cheaper; see ``.method`` and ``.reason``);
    ``harmonics`` is unused by the methods without the Hill operator.
    form: "direct" (Hill on M, C, K) or "inverse-mass" (the paper's eq. 26-27 on P, Q).
    truncation: what to do with a Hill result whose truncation indicator ``.truncation``
    (edge energy fraction) is above TRUNCATION_TOL: "refuse" (ConvergenceError naming the
    fix: more harmonics) or "warn" (TruncationWarning, the result is returned).
    """
    if truncation not in _TRUNCATION_CHOICES:
        raise InputError(f"truncation must be one of {_TRUNCATION_CHOICES}, got {truncation!r}")
    entry = method_named(method)
    op = HarmonicOperator.for_system(system, harmonics, form).at(system.omega) if entry.operator else None
    result = entry.exponents(system, op)
    if result.truncation > TRUNCATION_TOL:
        message = truncation_message(result.truncation, op.m, result.omega, result.method)
        if truncation == "refuse":
            raise ConvergenceError(f"{message}, or pass truncation='warn' to accept it with a warning")
        warnings.warn(message, TruncationWarning, stacklevel=2)
    return result


_TRUNCATION_CHOICES = ("refuse", "warn")
