"""Magnus monodromy matrices of rheo-linear systems and the certified Magnus ladder of the
stability method "auto".

The state matrix of y' = A(theta, omega) y, y = (a q, q'), theta = omega t, is a
polynomial in omega at fixed angles (``A = sum_p omega^p terms[p]``, :func:`magnus_terms`),
so its samples at the Gauss angles of a step count are built once per model and combined
per speed inside the jitted kernels (:mod:`periodyn.kernels.floquet`), for all speeds of a
chunk in one call. Two integrators: 4th order with two Gauss points per step, and 6th
order with three (six more matrix products a step, 64x smaller error per halving of h).

:class:`MagnusLadder` certifies the largest multiplier to ``STABILITY_TOL`` in log|mu| by
step doubling with an error estimate from successive rungs (see its docstring).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .errors import InputError
from .floquet import STABILITY_TOL
from .kernels.floquet import magnus_monodromies, magnus_product
from .spectra import StackedSpectra, real_basis

__all__ = ["gauss_angles", "magnus_terms", "magnus_transition", "magnus_steps", "monodromy_exponent_array",
           "half_period_signs", "MagnusEstimate", "MagnusLadder"]


def magnus_steps(samples: int) -> int:
    """Default Magnus steps per period for coefficients sampled p times: max(128, 2p)."""
    return max(128, 2 * samples)


_GAUSS_NODES = {2: np.array([0.5 - np.sqrt(3) / 6, 0.5 + np.sqrt(3) / 6]),
                3: np.array([0.5 - np.sqrt(15) / 10, 0.5, 0.5 + np.sqrt(15) / 10])}


def gauss_angles(steps: int, start: float = 0.0, stop: float = 2 * np.pi, points: int = 2) -> np.ndarray:
    """Angles of the ``points`` (2 or 3) Gauss points of each of ``steps`` equal steps,
    (points steps,), rad."""
    frac = (np.arange(steps)[:, None] + _GAUSS_NODES[points][None, :]).ravel() / steps
    return start + (stop - start) * frac


@lru_cache(maxsize=64)
def _angle_basis(K: int, steps: int, points: int, span: float) -> np.ndarray:
    """:func:`periodyn.spectra.real_basis` (points steps, 2K+1) at the Gauss angles of
    ``steps`` steps over [0, span] (read-only, shared between calls)."""
    basis = real_basis(K, gauss_angles(steps, 0.0, span, points))
    basis.flags.writeable = False
    return basis


def magnus_terms(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray) -> tuple[np.ndarray, float]:
    """Terms of the balanced first-order system matrix for the Magnus kernels.

    mass (g, n, n), damping (g, n, n, Pc), stiffness (g, n, n, Pk) at g points, the last
    axis holding the coefficients of powers of omega. Returns terms (max(Pc, Pk), g, 2n, 2n)
    with ``A = sum_p omega^p terms[p]`` the matrix of y' = A y for y = (a q, q'), and the
    balancing scale a = sqrt(max ||M^-1 K_0||_inf) (1/s), which brings the stiff blocks to
    the same size (a similarity: the transition matrix of (q, q') is D^-1 Phi D,
    D = diag(a I, I), with the same eigenvalues)."""
    g, n = mass.shape[:2]
    Pc, Pk = damping.shape[-1], stiffness.shape[-1]
    both = np.linalg.solve(mass, np.concatenate([damping.reshape(g, n, n * Pc), stiffness.reshape(g, n, n * Pk)], 2))
    MinvC, MinvK = both[..., :n * Pc].reshape(g, n, n, Pc), both[..., n * Pc:].reshape(g, n, n, Pk)
    top = float(np.abs(MinvK[..., 0]).sum(axis=2).max()) if g else 0.0
    a = np.sqrt(top) if top > 0 else 1.0
    terms = np.zeros((max(Pc, Pk), g, 2 * n, 2 * n))
    terms[0, :, :n, n:] = a * np.eye(n)
    terms[:Pk, :, n:, :n] = -np.moveaxis(MinvK, -1, 0) / a
    terms[:Pc, :, n:, n:] = -np.moveaxis(MinvC, -1, 0)
    return terms, a


def magnus_transition(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, h: float) -> np.ndarray:
    """Transition matrix (2n, 2n) of y' = A(t) y, y = (q, q'), over equal steps h (s).

    mass/damping/stiffness: (2 steps, n, n) at the two Gauss points of each step (see
    :func:`gauss_angles`); the jitted 4th-order Magnus kernel on the balanced system."""
    n = mass.shape[1]
    terms, a = magnus_terms(mass, damping[..., None], stiffness[..., None])
    phi = np.empty((2 * n, 2 * n))
    magnus_product(terms[0], float(h), phi)
    phi[:n, n:] /= a  # undo the balancing: Phi = D^-1 Phi_balanced D
    phi[n:, :n] *= a
    return phi


def monodromy_exponent_array(Phi: np.ndarray, omegas: np.ndarray) -> np.ndarray:
    """Exponents (S, d) from monodromy matrices (S, d, d) at speeds omegas (S,) rad/s: the
    principal logarithms of the multipliers (|Im| <= omega/2), sorted by real then
    imaginary part. A row with a zero multiplier (the monodromy underflowed: a mode decays
    by more than the double range, 1e-308, in one period, so its exponent is not
    determined) is NaN."""
    mu = np.linalg.eigvals(Phi).astype(complex)
    ok = np.all(mu != 0, axis=-1)
    lam = np.full(mu.shape, np.nan + 0j)
    lam[ok] = np.log(mu[ok]) * (np.asarray(omegas, float)[ok, None] / (2 * np.pi))
    return np.take_along_axis(lam, np.lexsort((lam.imag, lam.real), axis=-1), -1)




def half_period_signs(*spectra: np.ndarray, rtol: float = 1e-12) -> np.ndarray | None:
    """Signs s (n,) of a half-period symmetry ``X(theta + pi) = P X(theta) P``, P = diag(s),
    of every coefficient, or None if there is none.

    spectra: two-sided coefficient spectra (2K+1, n, n) or (2K+1, n, n, P). Entry (i, j)
    may have odd harmonics only if s_i = -s_j and even ones only if s_i = s_j (entries
    below rtol times the largest of their array count as zero); s by 2-colouring. Then
    the monodromy is ``(P Phi(T/2))^2`` with P acting on both q and q'."""
    n = spectra[0].shape[1]
    odd, even = np.zeros((n, n), bool), np.zeros((n, n), bool)
    for X in spectra:
        mag = np.abs(X).reshape(X.shape[0], n, n, -1).max(axis=-1)
        big = mag > rtol * mag.max()
        k = np.arange(X.shape[0]) - (X.shape[0] - 1) // 2
        odd |= big[k % 2 == 1].any(axis=0)
        even |= big[k % 2 == 0].any(axis=0)
    odd, even = odd | odd.T, even | even.T
    if (odd & even).any():
        return None
    signs = np.zeros(n)
    for root in range(n):
        if signs[root]:
            continue
        signs[root], stack = 1.0, [root]
        while stack:
            i = stack.pop()
            for j in np.nonzero(odd[i] | even[i])[0]:
                want = -signs[i] if odd[i, j] else signs[i]
                if signs[j] == 0:
                    signs[j] = want
                    stack.append(j)
                elif signs[j] != want:
                    return None
    return signs


# Seconds per Magnus step ~ (products + squarings) products of d x d matrices + a set-up
# (fitted on one core for d = 2..128: the jitted loops below d = 16, BLAS dgemm from there on)
_PRODUCT_RATE = (4.5e9, 1.2e10)  # flop/s of one product, below / from d = 16
_STEP_SETUP = 5.0e-7  # s per step
_STEP_PRODUCTS = {4: 6.0, 6: 12.0}  # products per step besides the squarings (commutators, Taylor)
#: Least error claimed for log|mu|: differences of rungs at the round-off level of N-step
#: products no longer estimate the error
ERROR_FLOOR = 1e-9


@dataclass(frozen=True, eq=False)
class MagnusEstimate:
    """Magnus monodromy exponents at S speeds with their error estimate.

    exponents (S, 2n) complex rad/s (principal values); accepted (S,) bool: the estimate
    certifies the result (else the speed needs another method); steps (S,) fine steps
    used (over the ladder's span: half a period for half-period-symmetric coefficients;
    0 where Magnus was not tried); error (S,) estimated error of log|mu| per period;
    margin (S,) distance of log max|mu| from the stability threshold; order (S,) the
    Magnus order used (4 or 6; 0 where not tried)."""

    exponents: np.ndarray
    accepted: np.ndarray
    steps: np.ndarray
    error: np.ndarray
    margin: np.ndarray
    order: np.ndarray
    first_cost: np.ndarray  # (S,) estimated seconds of the first comparison (first two rungs)


class MagnusLadder:
    """Magnus monodromy with step doubling, for one omega-polynomial model.

    mass (2K+1, n, n), damping (2K+1, n, n, Pc), stiffness (2K+1, n, n, Pk): two-sided
    spectra with omega powers last; order 6 (three Gauss points a step), 4 (two), or None:
    both, chosen per speed (below).

    At each speed the rungs N0, 2 N0, 4 N0, ... steps are computed. With G = log max|mu|
    and the sorted moduli of two successive rungs,
    ``e = max(|G_N - G_N/2|, max |sort|mu_N| - sort|mu_N/2|| / max|mu_N|)`` bounds the
    error of the N-step result whenever the error at least halves per doubling. For
    order 6, once three rungs show the method's order, ``r = e_N/2 / e_N >= 32``, the
    estimate is Richardson's with a factor 2 of safety, ``2 e / (min(r, 64) - 1)``; before
    that regime, and always for order 4 (whose error on the slider-crank falls erratically
    before its asymptotic regime: Richardson missed by 5-10x there), e itself is used. No
    estimate is below ERROR_FLOOR (round-off). A speed is accepted when the estimate is at
    most STABILITY_TOL max(1, |G_N|) (relative to a growth above 1 per period, where the
    verdict is clear) and the verdict cannot flip, ``|G_N - STABILITY_TOL| > error``;
    otherwise (also when the multipliers overflow: at low speeds the coarse steps span
    many vibration periods) N is doubled while the estimated cost stays within the
    speed's budget (and N <= LARGEST, fewer for large models: :meth:`max_steps`).

    First rungs and orders, per speed (so that a speed's result does not depend on the
    other speeds of the call): the first rung is START / 2 steps, or the first rung whose
    balanced generator size scale * span / (omega N) is at most FIRST_RHO
    (:meth:`first_rungs`: coarser rungs do not resolve the stiff modes of element models
    and cost the most squarings). With both orders, a speed whose first rung has at least
    STIFF steps takes order 4 (on the stiff slider-crank its error is smaller than order
    6's at the same steps), the others order 6 (:meth:`orders_at`).

    When the coefficients have a half-period symmetry (:func:`half_period_signs`), the
    steps cover half a period and the monodromy is ``(P Phi(T/2))^2``: the same step
    length at half the cost.
    """

    START = {4: 32, 6: 8}  # fine steps of the first comparison, at the least
    LARGEST = 4096  # steps
    STIFF = 16  # first-rung steps from which "both orders" takes order 4
    FIRST_RHO = 32.0  # largest balanced generator size scale * span / (omega steps) of a first rung
    FIRST_MAX = 128  # most steps of a first rung
    TERMS_ENTRIES = 4e7  # most entries of one rung's cached terms (320 MB), which bounds its steps

    def __init__(self, mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, order: int | None = None):
        if order not in (4, 6, None):
            raise InputError(f"the Magnus ladder has order 4 or 6 (or None: both), got {order!r}")
        self.orders = (6, 4) if order is None else (order,)
        self.spectra = (mass, damping, stiffness)
        self.n = mass.shape[1]
        # the three spectra stacked as real cosine/sine rows: their values at a rung's angles
        # take one product with a cached angle basis
        self._stacked = StackedSpectra(*self.spectra)
        self.signs = half_period_signs(mass, damping, stiffness)
        self.span = 2 * np.pi if self.signs is None else np.pi  # angle the steps cover, rad
        self._terms: dict[tuple[int, int], tuple[np.ndarray, float]] = {}
        self.scale = self.terms(self.START[self.orders[0]], self.orders[0])[1]

    def terms(self, steps: int, order: int = 6) -> tuple[np.ndarray, float]:
        """Terms of the balanced system matrix at the Gauss angles of ``steps`` steps of
        ``order`` over the span; over half a period, term p is divided by 2^p so that the
        kernel, given twice the speed, takes steps of span / (omega steps) with the right
        matrix."""
        if (order, steps) not in self._terms:
            basis = _angle_basis(self._stacked.harmonics, steps, order // 2, self.span)
            terms, a = magnus_terms(*self._stacked.split(basis @ self._stacked.rows))
            if self.signs is not None:
                terms = terms / (2.0 ** np.arange(terms.shape[0]))[:, None, None, None]
            self._terms[order, steps] = terms, a
        return self._terms[order, steps]

    def cost(self, omegas: np.ndarray, steps, order: int = 6) -> np.ndarray:
        """Estimated seconds (S,) of one monodromy with ``steps`` steps of ``order`` at
        speeds omegas: the squarings of the exponentials follow the balanced generator's
        size, scale * span / (omega steps)."""
        d = 2 * self.n
        rho = self.scale * self.span / (np.asarray(omegas, float) * steps)
        squarings = np.maximum(0.0, np.ceil(np.log2(np.maximum(rho, 1e-300) / 4.0)))
        product = 2.0 * d**3 / _PRODUCT_RATE[int(d >= 16)]
        return steps * ((_STEP_PRODUCTS[order] + squarings) * product + _STEP_SETUP)

    def first_rungs(self, omegas: np.ndarray, order: int = 6) -> np.ndarray:
        """Steps (S,) of a speed's first rung: START / 2, or more (up to FIRST_MAX) where
        the balanced step generator would exceed FIRST_RHO."""
        rho = self.scale * self.span / (np.asarray(omegas, float) * self.FIRST_RHO)
        steps = 2 ** np.ceil(np.log2(np.clip(rho, 1.0, self.FIRST_MAX))).astype(np.int64)
        return np.maximum(self.START[order] // 2, steps)

    def max_steps(self, order: int) -> int:
        """Most steps of a rung of ``order``: LARGEST, or fewer (a power of 2) where the
        rung's terms would exceed TERMS_ENTRIES."""
        per_step = (order // 2) * (2 * self.n) ** 2 * max(X.shape[-1] for X in self.spectra[1:])
        return int(min(self.LARGEST, 2 ** np.floor(np.log2(max(2.0, self.TERMS_ENTRIES / per_step)))))

    def orders_at(self, omegas: np.ndarray) -> np.ndarray:
        """Magnus order (S,) per speed: with both orders, 4 where the first rung of order 6
        has at least STIFF steps (stiff element models: there order 4 certifies with fewer
        steps, as its error is smaller at the same steps), else 6."""
        return self._plan(np.asarray(omegas, float))[0]

    def first_cost(self, omegas: np.ndarray) -> np.ndarray:
        """Estimated seconds (S,) of the first comparison (first two rungs) per speed."""
        return self._plan(np.asarray(omegas, float))[2]

    def _plan(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Order (S,), first rung (S,) and estimated seconds of the first two rungs (S,)
        per speed w (S,) rad/s."""
        first = self.first_rungs(w, self.orders[0])
        if len(self.orders) == 1:
            order = np.full(w.size, self.orders[0])
        else:
            order = np.where(first >= self.STIFF, 4, 6)
            stiff = order == 4
            if stiff.any():
                first[stiff] = self.first_rungs(w[stiff], 4)
        cost = np.zeros(w.size)
        for o in self.orders:
            mine = order == o
            if mine.any():
                cost[mine] = self.cost(w[mine], first[mine], o) + self.cost(w[mine], 2 * first[mine], o)
        return order, first, cost

    def _moduli(self, omegas: np.ndarray, steps: int, order: int) -> tuple[np.ndarray, np.ndarray]:
        """Exponents (S, 2n) and sorted multiplier moduli (S, 2n) with ``steps`` steps
        (NaN where the monodromy matrix is not finite)."""
        Phi = np.empty((omegas.size, 2 * self.n, 2 * self.n))
        terms = self.terms(steps, order)[0]
        if self.signs is None:
            magnus_monodromies(terms, omegas, Phi, order // 2)
        else:
            magnus_monodromies(terms, 2.0 * omegas, Phi, order // 2)  # Phi(T/2), see terms()
            Phi *= np.concatenate([self.signs, self.signs])[:, None]
            with np.errstate(all="ignore"):  # an overflow is caught as non-finite below
                Phi = Phi @ Phi
        finite = np.isfinite(Phi).all(axis=(1, 2))
        exps = np.full((omegas.size, 2 * self.n), np.nan + 0j)
        exps[finite] = monodromy_exponent_array(Phi[finite], omegas[finite])
        with np.errstate(over="ignore"):  # a multiplier beyond the double range is inf: not accepted
            return exps, np.sort(np.exp(exps.real * (2 * np.pi / omegas)[:, None]), axis=1)

    def _empty(self, S: int) -> MagnusEstimate:
        d = 2 * self.n
        return MagnusEstimate(np.full((S, d), np.nan + 0j), np.zeros(S, bool), np.zeros(S, np.int64),
                              np.full(S, np.inf), np.full(S, np.nan), np.zeros(S, np.int64), np.zeros(S))

    def solve(self, omegas, budget) -> MagnusEstimate:
        """Exponents at speeds omegas (S,) rad/s, each speed doubling its steps while the
        spent estimated cost stays within budget (S,) s."""
        w = np.asarray(omegas, float)
        S = w.size
        budget = np.broadcast_to(np.asarray(budget, float), (S,))
        out = self._empty(S)
        orders, first, out.first_cost[:] = self._plan(w)
        for order in self.orders:
            mine = np.nonzero(orders == order)[0]
            if mine.size:
                self._climb(w, budget, mine, first, out, order)
        return out

    def _climb(self, w, budget, idx, first, out, order) -> np.ndarray:
        """Step doubling in ``order`` from ``first[idx]`` steps at the speeds w[idx] (whose
        first comparison costs out.first_cost[idx]), filling out; returns the estimated
        seconds spent (S,)."""
        spent_all = np.zeros(w.size)
        rung = first[idx].copy()
        affordable = out.first_cost[idx] <= budget[idx]
        idx, rung = idx[affordable], rung[affordable]
        spent = np.zeros(idx.size)
        pending = self.cost(w[idx], rung, order)  # estimated seconds of each speed's next rung
        last = np.full((idx.size, 2 * self.n), np.nan)
        e_prev = np.full(idx.size, np.nan)
        active = np.arange(idx.size)
        richardson = 2.0 ** (order - 1) if order == 6 else np.inf
        largest = min(self.LARGEST, self.max_steps(order))
        rung = np.minimum(rung, largest // 2)
        while active.size:
            done = np.zeros(idx.size, bool)
            for steps in np.unique(rung[active]):
                sel = active[rung[active] == steps]
                ws = w[idx[sel]]
                spent[sel] += pending[sel]
                pending[sel] = self.cost(ws, 2 * steps, order)
                exps, mod = self._moduli(ws, int(steps), order)
                with np.errstate(all="ignore"):  # non-finite multipliers: error NaN, not accepted
                    top = np.log(mod[:, -1])
                    e = np.maximum(np.abs(top - np.log(last[sel, -1])), np.abs(mod - last[sel]).max(axis=1) / mod[:, -1])
                    r = e_prev[sel] / e
                    error = np.where(r >= richardson, 2.0 * e / (np.minimum(r, 2.0**order) - 1.0), e)
                    error = np.maximum(error, ERROR_FLOOR)
                    margin = np.abs(top - STABILITY_TOL)
                    ok = (error <= STABILITY_TOL * np.maximum(1.0, np.abs(top))) & (margin > error)
                compared = ~np.isnan(last[sel, -1]) | ~np.isfinite(mod[:, -1])  # a second rung (or a failure)
                target = idx[sel][compared]
                out.exponents[target], out.steps[target], out.order[target] = exps[compared], steps, order
                out.error[target], out.margin[target], out.accepted[target] = error[compared], margin[compared], ok[compared]
                last[sel], e_prev[sel] = mod, e
                stop = ok | (spent[sel] + pending[sel] > budget[idx[sel]]) | (2 * steps > largest)
                done[sel] = stop & compared
                rung[sel] = 2 * steps
            active = active[~done[active]]
        spent_all[idx] = spent
        return spent_all
