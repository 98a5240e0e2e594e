"""One stability method over chunks of speeds of a constant-speed model: the batch side of
the registry (:mod:`periodyn.stability.methods`), used by :class:`periodyn.speeds.SpeedSolver`.

Per chunk of speeds w (S,) rad/s, the method's ``choose`` (if any) names the method of each
speed and may solve some itself ("auto": the Magnus ladder); every remaining group of
speeds goes to its method's ``batch`` (stacked dense Hill, the Magnus kernel) or, without
one, speed by speed through its scalar entry point. A speed that fails keeps NaN
exponents and a message, never a result.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import ConvergenceError
from ..harmonic.batch_balance import DENSE_TERMS_BYTES
from ..harmonic.operator import HarmonicOperator
from ..results import STABILITY_RECORDS
from ..system import OmegaSplitModel
from .floquet import TRUNCATION_TOL, TruncationWarning, truncation_message
from .hill import dense_exponents_batch
from .methods import StabilityMethod, hill_costs_many, method_named

__all__ = ["SpeedStability"]

DENSE_HILL_ELEMENTS = 4_000_000  # matrix entries of the real first-order Hill matrices stacked in one call
_EXP_MAX = np.log(np.finfo(float).max)  # largest Re(lambda) T whose multiplier exp(lambda T) is finite


class SpeedStability:
    """Per-model data of one stability method for many speeds.

    model: the OmegaSplitModel; harmonic: its omega-polynomial Hill operator; method: a
    registered name. :meth:`prepared` gives what a method's ``prepare`` builds once per
    model (on first use); ``dense_hill``: stacked dense Hill evaluates
    the precomputed real first-order Hill terms (PW, 2N, 2N) while they fit in
    DENSE_TERMS_BYTES (a larger model builds its dense Hill matrix speed by speed; the terms
    of the 32-element slider-crank at m = 32: 2.8 GB).
    """

    def __init__(self, model: OmegaSplitModel, harmonic: HarmonicOperator, method: str):
        self.model, self.harmonic = model, harmonic
        self.method = method_named(method)
        self.m, self.n = harmonic.m, model.n
        used = [method_named(name) for name in (self.method.name, *self.method.delegates)]
        self.dense_hill = (any(entry.name == "dense" for entry in used)
                           and 8.0 * harmonic.powers * (2 * harmonic.pattern.size) ** 2 <= DENSE_TERMS_BYTES)

    def prepared(self, name: str):
        """What method ``name``'s ``prepare`` builds for the model (once per model, on first
        use: kept with the model, :meth:`~periodyn.system.OmegaSplitModel.derived`)."""
        return self.model.derived(f"prepared {name}", None, lambda: method_named(name).prepare(self.model))

    def hill_choices(self, w: np.ndarray) -> list[tuple[str, str, float]]:
        """Hill method at each speed, why, and its estimated seconds: a method that hands
        speeds to Hill chooses per speed by estimated cost
        (:func:`periodyn.stability.methods.hill_costs_many`); any other is "requested"."""
        if not self.method.delegates:
            return [(self.method.name, "requested", np.inf)] * w.size
        return [(m, r, c) for m, c, r in hill_costs_many(self.harmonic, w)]

    def choose(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Method names (S,), reasons (S,), exponents (S, 2n) and whether they are solved
        already (S,) at speeds w."""
        return self._choose(w)[:4]

    def _choose(self, w: np.ndarray) -> tuple:
        """:meth:`choose` and the per-speed records ({column: (S,)}, every column of
        STABILITY_RECORDS, fill values where the method records none)."""
        records = {name: np.full(w.size, fill) for name, fill in STABILITY_RECORDS.items()}
        if self.method.choose is None:
            return (np.full(w.size, self.method.name, dtype=object), np.full(w.size, "requested", dtype=object),
                    np.full((w.size, 2 * self.n), np.nan + 0j), np.zeros(w.size, dtype=bool), records)
        names, reasons, exps, solved, *recorded = self.method.choose(self, w)
        records.update(recorded[0] if recorded else {})
        return names, reasons, exps, solved, records

    def costs(self, w: np.ndarray, base: float) -> np.ndarray:
        """Estimated seconds (S,) of each speed whose harmonic balance costs ``base`` s."""
        if self.method.sweep_cost is None:
            return np.full(w.size, base)
        return self.method.sweep_cost(self, w, base)

    def solve(self, w: np.ndarray, judged: np.ndarray | None = None
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, np.ndarray]]:
        """Exponents (S, 2n) (NaN where failed), failure messages (S,), the method used (S,)
        and the per-speed records ({column of STABILITY_RECORDS: (S,)}) at speeds w. A Hill
        result whose truncation indicator is above TRUNCATION_TOL fails with a message and a
        TruncationWarning where ``judged`` (S,) (default: all; a sweep leaves out speeds
        whose periodic solution failed already)."""
        names, _, exps, solved, records = self._choose(w)
        message = np.full(w.size, "", dtype=object)
        edge = np.full(w.size, np.nan)
        for name in dict.fromkeys(names[~solved]):
            group = np.nonzero((names == name) & ~solved)[0]
            exps[group], message[group], edge[group] = self._group(method_named(name), w[group])
        # the multiplier exp(lambda T) must be a number: Re(lambda) T above the double range is no exponent
        growth = exps.real.max(axis=1) * (2 * np.pi / w)
        for i in np.nonzero((message == "") & (growth > _EXP_MAX))[0]:
            exps[i] = np.nan
            message[i] = (f"an exponent at omega = {w[i]:.6g} rad/s has Re(lambda) T = {growth[i]:.3g}, beyond the "
                          "range of the multiplier exp(lambda T): the model's coefficients are out of the range the "
                          "solver resolves (rescale it or add harmonics)")
        judged = np.ones(w.size, dtype=bool) if judged is None else judged
        truncated = np.nonzero((message == "") & judged & (edge > TRUNCATION_TOL))[0]
        for i in truncated:  # a Hill verdict that more harmonics could change is a failed point, never silent
            exps[i] = np.nan
            message[i] = truncation_message(edge[i], self.m, w[i], names[i])
        if truncated.size:
            warnings.warn(f"{truncated.size} of {w.size} speeds failed: {message[truncated[0]]}", TruncationWarning,
                          stacklevel=3)
        records["hill_truncation"] = edge
        return exps, message, names, records

    def _group(self, entry: StabilityMethod, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Exponents (S, 2n), messages (S,) and Hill truncation indicators (S,) (NaN without Hill)."""
        if entry.batch is None:
            return self.one_by_one(entry, w)
        out = entry.batch(self, w)
        return out if len(out) == 3 else (*out, np.full(w.size, np.nan))

    def one_by_one(self, entry: StabilityMethod, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Exponents (S, 2n), messages (S,) and truncation indicators (S,) (the largest Hill
        edge energy fraction, NaN without Hill) speed by speed through the scalar entry point."""
        exps = np.full((w.size, 2 * self.n), np.nan + 0j)
        message = np.full(w.size, "", dtype=object)
        edge = np.full(w.size, np.nan)
        for i in range(w.size):
            try:
                result = entry.exponents(self.model.at(w[i]) if entry.system else None,
                                         self.harmonic.at(w[i]) if entry.operator else None)
            except ConvergenceError as exc:
                message[i] = str(exc) or type(exc).__name__
            else:
                exps[i], edge[i] = result.exponents, result.truncation
        return exps, message, edge

    def dense_batch(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Dense Hill at speeds w: stacked LAPACK calls of at most DENSE_HILL_ELEMENTS entries
        where the terms fit (``dense_hill``); exponents (S, 2n), messages (S,) and truncation
        indicators (S,)."""
        if not self.dense_hill:
            return self.one_by_one(method_named("dense"), w)
        m, n = self.m, self.n
        chunk = max(1, DENSE_HILL_ELEMENTS // (2 * self.harmonic.pattern.size) ** 2)
        parts = [dense_exponents_batch(self.harmonic.real_first_order_many(w[i: i + chunk]), w[i: i + chunk], m, n)
                 for i in range(0, w.size, chunk)]
        exps, edges, found = (np.concatenate(x) for x in zip(*parts))
        message = np.full(w.size, "", dtype=object)
        for i in np.nonzero(found < 2 * n)[0]:
            exps[i] = np.nan
            message[i] = (f"Hill's method with m = {m} resolved {found[i]} of {2 * n} exponent "
                          f"clusters at omega = {w[i]:.6g} rad/s; increase harmonics")
        with np.errstate(invalid="ignore"):
            edge = np.where(np.isfinite(edges), edges, -np.inf).max(axis=1)
        return exps, message, np.where(edge == -np.inf, np.nan, edge)
