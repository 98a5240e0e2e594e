"""``continuation``: response curves of a ``periodyn.DAE`` by IHB or shooting.

A discretization (:class:`_IHB`, :class:`_Shooting`, :class:`_Implicit`, each a
:class:`_Discretization`) gives ``equations(X, omega, P)``,
``residual``, ``exponents`` (Floquet, or None) and ``solution``; the arc-length driver
(``palc``) sees only ``R(X, p)``; special points are classified and refined by ``events``.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from ..nonlinear.ihb_solver import IHBProblem, ihb
from ..stability.methods import check_method
from ..errors import InputError
from ..nonlinear.jacobian_reuse import ChordEquations
from ..nonlinear.elements import as_dae
from ..nonlinear.implicit import STEPS, ImplicitProblem
from ..nonlinear.shooting_solver import ShootingProblem, start_state
from .branch import Branch, SpecialPoint
from .events import (KINDS, SPECIAL_POINTS, check_events, classify, nearest_of_kind, null_vector, refine_crossing,
                     refine_fold, same_point)
from .palc import Arc, difference_step, first_point, trace

__all__ = ["ContinuationOptions", "trace_branch"]

_AT_START = 1e-8  # |test function| at the start point below which the start is the special point
_FTOL = {"fold": 1e-10, "crossing": 1e-9}  # |test function| at which a refinement stops (dp/ds; |mu| - 1 or |mu - 1|)
_REUSE_SIZE = 1000  # IHB unknowns from which the corrector reuses factorizations (palc, reuse mode)


@dataclass(frozen=True)
class ContinuationOptions:
    """Step control and discretization options of :func:`continuation`.

    ds, ds_min, ds_max: initial, smallest and largest arc-length step (scaled norm, see
    ``palc``); max_points: branch points at most; tol: residual max-norm (default 1e-8 for
    IHB, 1e-9 for shooting); max_iter: corrector Newton updates; samples: IHB samples p
    (default from H); subharmonic: nu (orbit period 2 pi nu / omega); stability: a method of
    ``orbit_exponents`` or None (IHB; shooting has its monodromy; default "auto", the registry's
    rule, with fixed-step Magnus at refined special points); shooting_samples: orbit samples of a shooting solution; confirm: True
    checks every special point (``confirm_special_points``, its defaults: truncation, then
    direct integration), "truncation" (the default) only against more harmonics
    (``check_truncation``: IHB branches), False not at all;
    shooting_method: "DOP853" (adaptive, variational equations), "implicit" (element
    models: the trapezoidal one-period map of ``periodyn.nonlinear.implicit`` with
    shooting_steps steps, the stiff case) or "auto" (implicit for element models, else DOP853).
    events: user events (``periodyn.Event``), located and recorded among the special points.
    """

    ds: float = 0.02
    ds_min: float = 1e-5
    ds_max: float = 0.2
    max_points: int = 400
    tol: float | None = None
    max_iter: int = 7
    samples: int | None = None
    subharmonic: int = 1
    stability: str | None = "auto"
    shooting_samples: int = 128
    confirm: bool | str = "truncation"
    shooting_method: str = "auto"
    shooting_steps: int = STEPS
    events: tuple = ()

    def __post_init__(self):
        object.__setattr__(self, "events", check_events(self.events))
        if not (0 < self.ds_min <= self.ds_max) or self.ds <= 0:
            raise InputError(f"steps must satisfy 0 < ds_min <= ds_max and ds > 0, got ds={self.ds}, "
                             f"ds_min={self.ds_min}, ds_max={self.ds_max}")
        if self.max_points < 2 or self.max_iter < 1:
            raise InputError("max_points must be >= 2 and max_iter >= 1")
        if self.confirm not in (True, False, "truncation"):
            raise InputError(f"confirm must be True, False or 'truncation', got {self.confirm!r}")
        if self.shooting_method not in ("auto", "DOP853", "implicit"):
            raise InputError(f"shooting_method must be 'auto', 'DOP853' or 'implicit', got {self.shooting_method!r}")
        if self.stability is not None:
            check_method(self.stability)


class _Discretization:
    """Residual R(X, omega, P) and Jacobian of a discretization's problem ``prob``:
    ``equations`` for the corrector (a subclass may reuse Jacobians), ``exact_equations``
    for tangents and special points, ``residual`` alone."""

    def exact_equations(self, X, om, P):
        return self.prob.equations(X, om, P)

    def equations(self, X, om, P):
        return self.exact_equations(X, om, P)

    def residual(self, X, om, P):
        return self.prob.residual(X, om, P)


class _IHB(_Discretization):
    def __init__(self, system, harmonics, opts: ContinuationOptions, initial, om0, P0):
        self.prob = IHBProblem(system, harmonics, opts.samples, opts.subharmonic)
        self.tol = 1e-8 if opts.tol is None else opts.tol
        self.stability = opts.stability
        n, L = system.n, self.prob.L
        self.groups = [np.arange(n * L), np.arange(n * L, self.prob.size)]
        X0 = self.prob.from_solution(initial) if initial is not None else self.prob.initial(omega=om0, params=P0)
        self.X0 = self.prob.newton(X0, om0, P0, self.tol).x

    def exact_equations(self, X, om, P):
        return self.prob.residual_jacobian(X, om, P)

    def exponents(self, X, om, P, refine: bool = False):  # refine: "auto" (certified to 1e-6) -> Magnus
        method = "magnus" if refine and self.stability == "auto" else self.stability  # (crossings to 1e-9)
        return None if method is None else self.prob.exponents(X, om, P, method)

    def solution(self, X, om, P, rn, it, exps):
        return self.prob.solution(X, om, P, rn, it, exps)


class _Shooting(_Discretization):
    def __init__(self, system, harmonics, opts: ContinuationOptions, initial, om0, P0, parameter=None):
        self.tol = 1e-9 if opts.tol is None else opts.tol
        self.H = harmonics
        if initial is None:  # start from the IHB orbit at the first parameter value
            initial = ihb(system, om0, harmonics, samples=opts.samples, subharmonic=opts.subharmonic, stability=None,
                          params=P0)
        q, qd = start_state(system, initial, om0, P0)
        self.prob = ShootingProblem(system, q, opts.subharmonic, samples=opts.shooting_samples, parameter=parameter)
        self.groups = None
        self.X0 = self.prob.newton(self.prob.state(q, qd), om0, P0, self.tol).x
        self.chord = ChordEquations(self.prob, self.tol)

    def equations(self, X, om, P):  # reused Jacobians between exact ones (nonlinear.chord)
        return self.chord.equations(X, om, P)

    def parameter_derivative(self, X, om, P):
        return self.chord.parameter_derivative(X, om, P)

    def exponents(self, X, om, P, refine: bool = False):
        return self.prob.exponents(X, om, P)

    def solution(self, X, om, P, rn, it, exps):
        return self.prob.solution(X, om, P, rn, it, exps, self.H)


class _Implicit(_Discretization):
    """Shooting on the trapezoidal one-period map of an element model (``ImplicitProblem``)."""

    def __init__(self, system, harmonics, opts: ContinuationOptions, initial, om0, P0):
        self.tol = 1e-9 if opts.tol is None else opts.tol
        self.H = harmonics
        self.prob = ImplicitProblem(system, opts.subharmonic, opts.shooting_steps, opts.shooting_samples, self.tol)
        if initial is None:
            initial = ihb(system, om0, harmonics, samples=opts.samples, subharmonic=opts.subharmonic, stability=None,
                          params=P0)
        q, qd = start_state(system, initial, om0, P0)
        self.groups = None
        self.X0 = self.prob.newton(self.prob.state(q, qd), om0, P0, self.tol).x
        self._last = (None, None)

    def _solution(self, X, om, P):
        key = (np.asarray(X, float).tobytes(), float(om))
        if self._last[0] != key:
            self._last = (key, self.prob.solution(X, om, P, 0.0, 0, self.H))
        return self._last[1]

    def exponents(self, X, om, P, refine: bool = False):  # of the extrapolated monodromy, as pointwise shooting
        return self._solution(X, om, P).stability

    def solution(self, X, om, P, rn, it, exps):
        return replace(self._solution(X, om, P), residual=float(rn), iterations=int(it))


def _implicit(system, opts: ContinuationOptions) -> bool:
    """Whether shooting continuation uses the implicit map (option, or "auto": element models)."""
    if opts.shooting_method != "auto":
        return opts.shooting_method == "implicit"
    return hasattr(getattr(system, "equations", None), "configurations")


def trace_branch(system, omega, harmonics: int = 5, method: str = "ihb", parameter: tuple | None = None, *,
                 initial=None, tangent=None, options: ContinuationOptions | None = None, progress=None,
                 **option_values) -> Branch:
    """Response curve of a ``periodyn.DAE`` or an element model (its non-linear equations,
    ``element_dae``) by pseudo-arc-length continuation -> Branch.

    omega: (start, stop) rad/s for a frequency response, or a fixed value when
    ``parameter=(name, start, stop)`` continues a named parameter; start and stop finite,
    distinct and, for omega, positive: the branch stays between them and ends exactly on stop
    (or on start when it turns back out of the range; ``palc.trace``). method: "ihb" (H =
    harmonics) or "shooting" (spectra truncated to H). initial: a PeriodicSolution at the
    start (else solved from ``system.q0``). tangent: initial (dX, dp) (branch switching:
    only omega > 0 and the side of stop bound the branch).
    options: ContinuationOptions; keyword values (ds=..., stability=..., ...) override its
    fields. progress: None or a callable (points so far, parameter value (omega for a
    frequency response) of the newest point). Every point carries its residual and Newton iterations (chord
    updates for IHB problems of ``_REUSE_SIZE`` unknowns or more, see ``palc``); non-converged points are never
    recorded.
    """
    opts = replace(options or ContinuationOptions(), **_known(option_values))
    system = as_dae(system, "continuation")
    name, p0, p1 = _range(system, omega, parameter)

    def at(p):
        """(omega, parameters) of parameter value p."""
        return (p, system.parameters) if name is None else (float(omega), dict(system.parameters, **{name: p}))

    if method not in ("ihb", "shooting"):
        raise InputError(f"method must be 'ihb' or 'shooting', got {method!r}")
    if method == "ihb":  # a frequency response: dR/domega with the samples of X taken once
        disc = _IHB(system, harmonics, opts, initial, *at(p0))
        dR_dp = (lambda X, p: disc.prob.omega_derivative(X, p, difference_step(p))) if name is None else None
    elif _implicit(system, opts):
        if name is not None:
            raise InputError("shooting on the implicit map continues omega only; give shooting_method='DOP853' "
                             "for a parameter curve")
        disc, dR_dp = _Implicit(system, harmonics, opts, initial, *at(p0)), None
    else:
        disc = _Shooting(system, harmonics, opts, initial, *at(p0), parameter=name)
        dR_dp = lambda X, p: disc.parameter_derivative(X, *at(p))  # noqa: E731
    arc = Arc(lambda X, p: disc.equations(X, *at(p)), lambda X, p: disc.residual(X, *at(p)), disc.groups, disc.X0,
              p0, disc.tol, opts.max_iter, dR_dp, exact_tangents=isinstance(disc, _Shooting),
              reuse=method == "ihb" and disc.prob.size >= _REUSE_SIZE)

    def record(pt, refine=False):
        exps = disc.exponents(pt.X, *at(pt.p), refine=refine)
        return disc.solution(pt.X, *at(pt.p), pt.residual, pt.iterations, exps)

    pts = [first_point(arc, disc.X0, p0, p1, tangent)]
    sols = [record(pts[0], refine=tangent is not None)]  # precise: a switched branch starts on its special point
    tests = [[ev.value(sols[0], pts[0].p) for ev in opts.events]]  # user event tests at each point
    specials, status, loose, unknowns = [], "", set(), {}
    bounds = (min(p0, p1), max(p0, p1)) if tangent is None else None  # a switched branch may turn back past its start
    for item in trace(arc, pts[0], p1, ds=opts.ds, ds_min=opts.ds_min, ds_max=opts.ds_max, max_points=opts.max_points,
                      bounds=bounds, positive=name is None):
        if isinstance(item, str):
            status = item
            break
        pts.append(item)
        sols.append(record(item))
        if progress is not None:
            progress(len(pts), item.p)
        for sp, unbracketed, X in _special_points(arc, disc, at, pts[-2], pts[-1], sols[-2], sols[-1], len(pts) - 2):
            unknowns[id(sp)] = X
            _add_special(specials, sp, [pt.p for pt in pts], unbracketed, loose)
        tests.append([ev.value(sols[-1], item.p) for ev in opts.events])
        for sp, X in _user_points(arc, disc, at, opts.events, pts[-2:], sols[-2:], tests[-2:], len(pts) - 2):
            unknowns[id(sp)] = X
            specials.append(sp)
    options = dict(method=method, harmonics=harmonics, system=system, tol=disc.tol,
                   special_unknowns=tuple(unknowns[id(sp)] for sp in specials),
                   samples=getattr(disc.prob, "p", None), **{f.name: getattr(opts, f.name) for f in fields(opts)
                                                           if f.name not in ("tol", "samples")})
    branch = Branch.from_solutions(sols, [pt.p for pt in pts], name, specials, status, disc.prob, options,
                                   np.array([pt.X for pt in pts]))
    return branch


def _range(system, omega, parameter) -> tuple[str | None, float, float]:
    """(name or None, start, stop); refuses a range not two numbers, empty, infinite or (omega) not > 0."""
    given = omega if parameter is None else parameter
    try:  # a string is no range ("12" would be (1, 2))
        if isinstance(given, (str, bytes)) or (parameter is not None and parameter[0] not in system.parameters):
            raise TypeError
        name, p0, p1 = (None, *map(float, omega)) if parameter is None else (parameter[0], *map(float, parameter[1:]))
    except (TypeError, ValueError, IndexError):
        raise InputError(("omega must be (start, stop) in rad/s, or give parameter=(name, start, stop)" if parameter
                          is None else f"parameter must be (name, start, stop) with name in {sorted(system.parameters)}")
                         + f"; got {given!r}") from None
    what = "omega=(start, stop) in rad/s" if name is None else f"parameter=({name!r}, start, stop)"
    if not (np.isfinite(p0) and np.isfinite(p1)):
        raise InputError(f"{what} must be finite, got ({p0}, {p1}); give both ends as numbers")
    if name is None and not (p0 > 0 and p1 > 0):
        raise InputError(f"{what} must be positive driving speeds, got ({p0}, {p1}); give 0 < start, stop")
    if p0 == p1:
        raise InputError(f"{what} is empty: start and stop are both {p0}; give two different values")
    return name, p0, p1


def _known(values: dict) -> dict:
    names = {f.name for f in fields(ContinuationOptions)}
    unknown = set(values) - names
    if unknown:
        raise InputError(f"unknown continuation option(s) {sorted(unknown)}; options are {sorted(names)}")
    return values


def _add_special(specials: list, sp: SpecialPoint, p: list, unbracketed: bool, loose: set) -> None:
    """Append sp to specials unless a point of its type in the adjacent bracket before it
    is the same point: both refined and one to the refinement tolerance
    (``events.same_point``; the one with the smaller |test function| stays), or one refined
    and the other ``unbracketed`` (the multiplier count changed in its bracket but its test
    function did not change sign: the count saw the crossing refined next door; the refined
    one stays). p: parameter values of the branch points so far (p[k] is the point the two
    brackets share); loose: ids of the unbracketed points in specials (updated)."""
    k = sp.index
    for i, q in enumerate(specials):
        if q.type != sp.type or q.index != k - 1:
            continue
        refined = q.test_values is not None, sp.test_values is not None
        if refined == (True, False) and unbracketed:
            return
        if refined == (False, True) and id(q) in loose:
            loose.discard(id(q))
            specials[i] = sp
            return
        if all(refined) and same_point(q.parameter, q.test_values[2], sp.parameter, sp.test_values[2], p[k],
                                       sp.test_values[0], _FTOL["fold" if sp.type == "fold" else "crossing"]):
            if abs(sp.test_values[2]) < abs(q.test_values[2]):
                specials[i] = sp
            return
    if unbracketed:
        loose.add(id(sp))
    specials.append(sp)


def _special_points(arc, disc, at, a, b, sol_a, sol_b, k) -> list[tuple[SpecialPoint, bool, np.ndarray | None]]:
    """Classified and refined special points between accepted points a and b (index k),
    each with whether its test function failed to change sign over the bracket and with
    the discretization's unknowns there (None when refinement failed; branch switching
    starts from them)."""
    out = []
    for typ, crit, s_lin in classify(a.t[arc.N], b.t[arc.N], sol_a.multipliers, sol_b.multipliers):
        if typ == "fold":
            found = refine_fold(arc, a, b, _FTOL["fold"])
        else:
            test = SPECIAL_POINTS[typ]
            bracket = (test(sol_a.multipliers), test(sol_b.multipliers))
            if k == 0 and abs(bracket[0]) < _AT_START:
                continue  # the start is this special point itself (a branch switched from it)
            value = lambda X, p, test=test: test(disc.exponents(X, *at(p), refine=True).multipliers)  # noqa: E731
            found = refine_crossing(lambda X, p: disc.exact_equations(X, *at(p)), arc.tol, a, b, value, bracket,
                                    _FTOL["crossing"])
        if found is None:  # refinement failed: linear interpolation, no orbit
            p = a.p + s_lin * (b.p - a.p)
            amp = sol_a.amplitude() + s_lin * (sol_b.amplitude() - sol_a.amplitude())
            unbracketed = typ != "fold" and not np.sign(bracket[0]) * np.sign(bracket[1]) < 0
            out.append((SpecialPoint(typ, k, float(at(p)[0]), float(p), crit, amp, None), unbracketed, None))
            continue
        X, p, rn, tests = found
        exps = disc.exponents(X, *at(p), refine=typ != "fold")  # a fold's test is dp/ds, not the multipliers
        sol = disc.solution(X, *at(p), rn, 0, exps)
        if typ != "fold":
            mu = sol.multipliers
            crit = complex(mu[int(np.argmin(np.abs(mu - 1)))]) if typ == "branch-point" else nearest_of_kind(
                mu, KINDS[typ])
        vec = null_vector(disc.equations(X, *at(p))[1]) if typ in ("fold", "branch-point") else None
        out.append((SpecialPoint(typ, k, float(at(p)[0]), float(p), crit, sol.amplitude(), sol, vec,
                                 np.asarray(tests, float)), False, np.array(X, float)))
    return out


def _user_points(arc, disc, at, events, points, sols, tests, k) -> list[tuple[SpecialPoint, np.ndarray | None]]:
    """Special points of the user events whose tests (``tests``: their values at the two
    accepted ``points`` of index k, k + 1, orbits ``sols``) change sign there, located by
    ``events.refine_crossing`` (linear interpolation without an orbit when it fails), each
    with the unknowns there."""
    (a, b), (sol_a, sol_b) = points, sols

    def orbit(X, p, rn=0.0):
        return disc.solution(X, *at(p), rn, 0, disc.exponents(X, *at(p)))

    out = []
    for ev, ga, gb in zip(events, *tests):
        if not np.sign(ga) * np.sign(gb) < 0:
            continue
        found = refine_crossing(lambda X, p: disc.exact_equations(X, *at(p)), arc.tol, a, b,
                                lambda X, p, ev=ev: ev.value(orbit(X, p), p), (ga, gb), ev.tol)
        if found is None:
            s = ga / (ga - gb)
            p, amp = a.p + s * (b.p - a.p), sol_a.amplitude() + s * (sol_b.amplitude() - sol_a.amplitude())
            out.append((SpecialPoint(ev.name, k, float(at(p)[0]), float(p), amplitude=amp), None))
            continue
        X, p, rn, values = found
        sol = orbit(X, p, rn)
        out.append((SpecialPoint(ev.name, k, float(at(p)[0]), float(p), complex("nan"), sol.amplitude(), sol, None,
                                 np.asarray(values, float)), np.array(X, float)))
    return out
