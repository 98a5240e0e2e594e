"""Two-parameter stability charts: the stability boundaries of a periodic-coefficient
system followed in the (omega, p) plane, p a model parameter (a misalignment, a damping).

A boundary is a curve of g(omega, p) = max Re(lambda) = 0 (1/s), where a Floquet multiplier
sits on the unit circle: at +1 ("fold"), -1 ("period-doubling") or exp(i phi)
("neimark-sacker"), typed by the one classifier (:mod:`periodyn.stability.crossings`).

How it is followed: every boundary found by bisection on a speed grid at a seed value of p
is continued over the parameter grid by natural-parameter continuation with a secant
(tangent) predictor in omega and a bracketed corrector: from the predicted speed the
bracket grows until g changes sign with the boundary's own orientation (stable on the
same side), never past half-way to the neighbouring boundaries, and Brent's method refines
it. Why this and not pseudo-arclength on g = 0: a new p means a new model (for the Cardan
shaft a re-linearization costing 10-20 exponent evaluations), and stepping in p lets every
boundary share one model per parameter value while a Newton corrector moves p at every
iteration; the bracket guarantees a root of the right orientation, where Newton may jump
to the neighbouring boundary of a narrow zone. The turning points that pseudo-arclength
passes (a zone, or a stable gap, closing as p changes: its two boundaries meet) are found
as such: when both neighbours lose their bracket, the tip is the root in p of the extremum
over omega of g between them (Brent on p, a bounded Brent maximization in omega), and the
two boundaries are joined through it into one curve, as pseudo-arclength would have drawn
it. Where the brackets fail otherwise the step in p is halved, at most ``max_halvings``
times, then the curve ends flagged "lost", never silently.
"""

from __future__ import annotations

from collections import OrderedDict
from typing import Any, Callable

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ..errors import InputError
from .boundaries import StabilityBoundary, check_boundary, crossing_type
from .chart_data import ChartBoundary, ChartCheck, ChartOptions, StabilityChart
from .methods import characteristic_exponents

__all__ = ["stability_chart", "check_chart"]

_TYPE_STEP = 1e-6    # relative distance into the unstable side at which a boundary point is typed
_MODELS_KEPT = 4     # models kept per chart (the parameter values last built)


class _Trace:
    """A boundary being followed from its seed: points per direction, how each end stops."""

    def __init__(self, seed: StabilityBoundary, p: float):
        self.side = 1 if seed.becomes_stable else -1
        self.seed = (p, seed.omega, seed.kind, self.side)
        self.points = {-1: [], 1: []}
        self.end: dict[int, Any] = {}

    def last(self, d: int, back: int = 1):
        pts = [self.seed] + self.points[d]
        return pts[-back] if len(pts) >= back else None


class _Chart:
    """The exponent evaluations of one chart, with its models cached by parameter value."""

    def __init__(self, model_at: Callable, omega: np.ndarray, options: ChartOptions, span: float):
        self.model_at, self.omega, self.o, self.span = model_at, omega, options, span
        self.models: OrderedDict = OrderedDict()
        self.evaluations = self.builds = 0

    def system_at(self, p: float) -> Callable:
        if p not in self.models:
            model = self.model_at(float(p))
            self.models[p] = getattr(model, "at", model)
            self.builds += 1
            if len(self.models) > _MODELS_KEPT:
                self.models.popitem(last=False)
        self.models.move_to_end(p)
        return self.models[p]

    def exponents(self, p: float, w: float):
        self.evaluations += 1
        return characteristic_exponents(self.system_at(p)(float(w)), self.o.harmonics, self.o.method,
                                        truncation=self.o.truncation)

    def g(self, p: float, w: float) -> float:
        return float(self.exponents(p, w).max_real)

    def kind(self, p: float, w: float, side: int) -> str:
        return crossing_type(self.exponents(p, w * (1.0 - side * _TYPE_STEP)))

    def seeds(self, p: float) -> list[StabilityBoundary]:
        """The boundaries at p between the speeds of the grid where g changes sign, by Brent."""
        values = np.array([self.g(p, w) for w in self.omega])
        found = []
        for i in np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0):
            w = self.root(p, self.omega[i], self.omega[i + 1])
            side = 1 if values[i + 1] < 0 else -1
            found.append(StabilityBoundary(w, self.kind(p, w, side), side > 0))
        return found

    # ---------------------------------------------------------------- corrector
    def bracket(self, p, w0, side, lo, hi, delta):
        """(a, b) with g of the boundary's below sign at a and above sign at b, grown from
        w0 within [lo, hi]; or (None, direction searched) when there is none."""
        below = float(side)     # g > 0 below a boundary stable above it
        v = self.g(p, w0)
        up = np.sign(v) == below
        a, step = w0, delta
        while True:
            b = min(a + step, hi) if up else max(a - step, lo)
            vb = self.g(p, b)
            if np.sign(vb) != (below if up else -below):
                return (a, b) if up else (b, a)
            if b in (lo, hi):
                return None, (1 if up else -1)
            a, step = b, 2.0 * step

    def root(self, p, a, b) -> float:
        return brentq(lambda w: self.g(p, w), a, b, xtol=self.o.xtol * a, rtol=4 * np.finfo(float).eps)

    def extremum(self, p, lo, hi, sign) -> tuple[float, float]:
        """(sign * extremum of g near [lo, hi], where) at parameter p (a bounded Brent; the
        interval is widened by its width, up to 8 times, while the extremum is at an end:
        a closing zone may drift out of where it was at the last step)."""
        for _ in range(9):
            res = minimize_scalar(lambda w: -sign * self.g(p, w), bounds=(lo, hi), method="bounded",
                                  options={"xatol": 1e-7 * hi})
            width, at = hi - lo, float(res.x)
            if at - lo < 1e-2 * width and lo > self.omega[0]:
                lo = max(lo - width, self.omega[0])
            elif hi - at < 1e-2 * width and hi < self.omega[-1]:
                hi = min(hi + width, self.omega[-1])
            else:
                break
        return -float(res.fun), at

    def step(self, traces: list[_Trace], d: int, p_new: float):
        """Follow ``traces`` (by increasing omega) to p_new: (roots found {i: omega}, closing
        pairs i (with i + 1), exits from the window, stray failures (halve the step))."""
        old = [t.last(d) for t in traces]
        pred = []
        for t, (p0, w0, _, _) in zip(traces, old):
            prev = t.last(d, 2)
            pred.append(w0 if prev is None else w0 + (w0 - prev[1]) / (p0 - prev[0]) * (p_new - p0))
        pred = np.asarray(pred)
        if np.any(np.diff(pred) <= 0) or pred[0] <= self.omega[0] or pred[-1] >= self.omega[-1]:
            pred = np.array([w for _, w, _, _ in old])   # the zero-order predictor keeps the order
        edges = np.concatenate([[self.omega[0]], 0.5 * (pred[1:] + pred[:-1]), [self.omega[-1]]])
        found, failed = {}, {}
        for i, t in enumerate(traces):
            delta = max(2.0 * abs(pred[i] - old[i][1]), 1e-3 * pred[i])
            got = self.bracket(p_new, pred[i], t.side, edges[i], edges[i + 1], delta)
            if got[0] is None:
                failed[i] = got[1]
            else:
                found[i] = self.root(p_new, *got)
        def toward_edge(i):   # the root runs out of the window: it was near the edge, moving to it
            edge = self.omega[0] if failed[i] < 0 else self.omega[-1]
            return abs(edge - old[i][1]) <= 4.0 * max(abs(pred[i] - old[i][1]), 1e-3 * pred[i])

        exits = [i for i in failed if ((i == 0 and failed[i] < 0) or (i == len(traces) - 1 and failed[i] > 0))
                 and toward_edge(i)]
        pairs = [i for i in failed if failed[i] > 0 and failed.get(i + 1) == -1]
        stray = sorted(set(failed) - set(exits) - set(pairs) - {i + 1 for i in pairs})
        return found, pairs, exits, stray

    def tip(self, a: _Trace, b: _Trace, d: int, p_old: float, p_new: float, found: dict, ia: int):
        """Where the zone (or gap) between a and b closes between p_old and p_new: the tip
        (p, omega, kind), or the two boundaries at p_new when they exist after all
        (a narrow zone the bracket stepped over)."""
        sign = 1.0 if a.side < 0 else -1.0       # unstable zone between: its max; stable gap: its min
        lo, hi = a.last(d)[1], b.last(d)[1]
        h_new, w_new = self.extremum(p_new, lo, hi, sign)
        if h_new > 0:
            if not lo < w_new < hi:
                return None
            ends = (self.g(p_new, lo), self.g(p_new, hi))
            if np.sign(ends[0]) == sign or np.sign(ends[1]) == sign:
                return None
            found[ia], found[ia + 1] = self.root(p_new, lo, w_new), self.root(p_new, w_new, hi)
            return "found"
        if self.extremum(p_old, lo, hi, sign)[0] <= 0:
            return None
        p_tip = brentq(lambda q: self.extremum(q, lo, hi, sign)[0], p_old, p_new, xtol=self.o.ptol * self.span)
        w_tip = self.extremum(p_tip, lo, hi, sign)[1]
        return (p_tip, w_tip, crossing_type(self.exponents(p_tip, w_tip)), 0)

    # ---------------------------------------------------------------- march
    def march(self, traces: list[_Trace], grid: np.ndarray, s: int, d: int) -> None:
        """Follow ``traces`` (seeded at grid[s]) over the grid in direction d (+1 up, -1 down)."""
        active = list(traces)
        targets = grid[s + 1:] if d > 0 else grid[:s][::-1]
        p_old = grid[s]
        for target in targets:
            while active and p_old != target:
                p_new = target
                for halving in range(self.o.max_halvings + 1):
                    found, pairs, exits, stray = self.step(active, d, p_new)
                    last = halving == self.o.max_halvings
                    result = None if stray and not last else self._close(active, d, p_old, p_new, found, pairs, exits)
                    if result is not None and np.all(np.diff([found[i] for i in sorted(found)]) > 0):
                        break
                    result = None
                    p_new = 0.5 * (p_old + p_new)
                if result is None:
                    for t in active:
                        t.end[d] = f"lost: no tip between p = {p_old:.6g} and {p_new:.6g} after halvings"
                    return
                for i in stray:
                    active[i].end[d] = (f"lost: no root near the prediction at p = {p_new:.6g} and no neighbour "
                                        "followed (a boundary outside the speed window at the seeds? widen omega)")
                found, joins, exits = result
                for i, j, tip in joins:
                    active[i].end[d], active[j].end[d] = ("join", active[j], tip), ("join", active[i], tip)
                for i in exits:
                    active[i].end[d] = "omega"
                for i, t in enumerate(active):
                    if i in found:
                        t.points[d].append((p_new, found[i], self.kind(p_new, found[i], t.side), t.side))
                active = [t for i, t in enumerate(active) if i in found]
                p_old = p_new
        for t in active:
            t.end[d] = "range"

    def _close(self, active, d, p_old, p_new, found, pairs, exits):
        """Resolve the failed brackets of one step: (found, joins (i, i + 1, tip), exits);
        a closing pair is joined at its tip or found after all. None: halve the step."""
        joins = []
        for i in pairs:
            got = self.tip(active[i], active[i + 1], d, p_old, p_new, found, i)
            if got is None:
                return None
            if got != "found":
                joins.append((i, i + 1, got))
        return found, joins, exits


def stability_chart(model_at: Callable[[float], Any], omega, parameter, options: ChartOptions, *,
                    seeds=None, name: str = "parameter") -> StabilityChart:
    """The stability boundaries of ``model_at(p)`` (an OmegaSplitModel, or any callable of
    omega in rad/s returning a RheoLinear) over the parameter grid ``parameter`` (P,),
    increasing, within the speed window of ``omega`` (S,), increasing rad/s: the bisection
    grid of the seeds. seeds: parameter values (of the grid) where the boundaries are found
    by bisection and from which they are followed both ways (default: both grid ends);
    a boundary a later seed finds on a curve already followed is not followed again."""
    omega, grid = np.asarray(omega, float), np.asarray(parameter, float)
    for label, x in (("omega", omega), ("parameter", grid)):
        if x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)) or np.any(np.diff(x) <= 0):
            raise InputError(f"{label} must be an increasing 1-D grid of at least two finite values")
    if not isinstance(options, ChartOptions):
        raise InputError(f"options must be a periodyn.stability.charts.ChartOptions, got {type(options).__name__}")
    seeds = (grid[0], grid[-1]) if seeds is None else tuple(float(s) for s in np.atleast_1d(seeds))
    missing = [s for s in seeds if not np.any(grid == s)]
    if missing:
        raise InputError(f"seeds {missing} are not values of the parameter grid; give seeds from the grid")
    chart = _Chart(model_at, omega, options, grid[-1] - grid[0])
    traces: list[_Trace] = []
    for p in seeds:
        s = int(np.flatnonzero(grid == p)[0])
        known = [w for t in traces for q, w, _, _ in [t.seed, *t.points[-1], *t.points[1]] if q == p]
        new = [_Trace(b, p) for b in chart.seeds(p)
               if not any(abs(b.omega - w) <= 1e3 * options.xtol * w for w in known)]
        if not new:
            continue
        for d in (-1, 1):
            chart.march(new, grid, s, d)
        traces += new
    curves = tuple(_curves(traces))
    return StabilityChart(name, grid, omega, seeds, curves, options, chart.evaluations, chart.builds)


def _curves(traces: list[_Trace]):
    """The traces joined at their tips into curves (ChartBoundary each)."""
    seen: set[int] = set()
    starts = [(t, d) for t in traces for d in (-1, 1) if not isinstance(t.end[d], tuple)]
    starts += [(t, -1) for t in traces]   # closed loops: any trace, once the open ones are done
    for first, d0 in starts:
        if id(first) in seen:
            continue
        pts, t, d, ends = [], first, d0, [first.end[d0] if not isinstance(first.end[d0], tuple) else "loop"]
        while True:
            seen.add(id(t))
            pts += t.points[d][::-1] + [t.seed] + t.points[-d]
            end = t.end[-d]
            if not isinstance(end, tuple):
                ends.append(end)
                break
            _, other, tip = end
            pts.append(tip)
            if id(other) in seen:
                ends.append("loop")
                break
            t, d = other, -d
        p, w, kind, side = zip(*pts)
        yield ChartBoundary(np.array(p), np.array(w), np.array(kind, dtype=object), np.array(side, dtype=np.int8),
                            (ends[0], ends[1]))


def check_chart(model_at: Callable[[float], Any], chart: StabilityChart, points: int = 3,
                step: float = 1e-3) -> tuple[ChartCheck, ...]:
    """Monodromy checks (DOP853, :func:`periodyn.stability.boundaries.check_boundary`) of
    ``points`` boundary points per curve, evenly spread over its non-tip points, each at a
    relative distance ``step`` from the boundary (less where another boundary at the same p
    is nearer than 4 step omega)."""
    if not isinstance(points, int) or points < 1:
        raise InputError(f"points (checked per boundary) must be an integer >= 1, got {points!r}")
    out = []
    for index, b in enumerate(chart.boundaries):
        plain = np.flatnonzero(b.side != 0)
        for j in plain[np.unique(np.linspace(0, plain.size - 1, points).round().astype(int))]:
            p, w = float(b.parameter[j]), float(b.omega[j])
            others = [o for o, _, _ in chart.at(p) if o != w]
            gap = min((abs(o - w) for o in others), default=np.inf) / w
            model = model_at(p)
            system_at = getattr(model, "at", model)
            boundary = StabilityBoundary(w, str(b.kind[j]), bool(b.side[j] > 0))
            out.append(ChartCheck(index, p, check_boundary(system_at, boundary, min(step, 0.25 * gap))))
    return tuple(out)
