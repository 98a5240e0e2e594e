"""Magnus monodromy matrices of rheo-linear systems and the certified Magnus ladder of the
stability method "auto".

The state matrix of y' = A(theta, omega) y, y = (a q, q'), theta = omega t, is a
polynomial in omega at fixed angles (``A = sum_p omega^p terms[p]``, :func:`magnus_terms`),
so its samples at the Gauss angles of a step count are built once and combined per speed
inside the jitted kernels (:mod:`periodyn.kernels.solvers.floquet`), for all speeds of a chunk in
one call. Two integrators: 4th order with two Gauss points per step, and 6th order with
three (six more matrix products a step, 64x smaller error per halving of h).

:class:`MagnusLadder` certifies the largest multiplier to ``STABILITY_TOL`` in log|mu| by
step doubling with an error estimate from successive rungs (see its docstring); its whole
climb, for one speed or a chunk, is one kernel call
(:func:`periodyn.kernels.solvers.magnus_ladder.ladder_climb`), so a single speed costs little more
than its arithmetic.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .floquet import STABILITY_TOL
from ..kernels.solvers import magnus_ladder as kernel
from ..kernels.solvers.floquet import magnus_monodromies, magnus_product
from ..numerics.spectra import StackedSpectra

__all__ = ["gauss_angles", "magnus_terms", "magnus_transition", "magnus_steps", "monodromy_exponent_array",
           "half_period_signs", "MagnusEstimate", "MagnusLadder", "sweep_terms", "sweep_exponents"]


def magnus_steps(samples: int) -> int:
    """Default Magnus steps per period for coefficients sampled p times: max(128, 2p)."""
    return max(128, 2 * samples)


_GAUSS_NODES = {2: kernel.GAUSS_NODES_2, 3: kernel.GAUSS_NODES_3}


def gauss_angles(steps: int, start: float = 0.0, stop: float = 2 * np.pi, points: int = 2) -> np.ndarray:
    """Angles of the ``points`` (2 or 3) Gauss points of each of ``steps`` equal steps,
    (points steps,), rad."""
    frac = (np.arange(steps)[:, None] + _GAUSS_NODES[points][None, :]).ravel() / steps
    return start + (stop - start) * frac


def magnus_terms(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray) -> tuple[np.ndarray, float]:
    """Terms of the balanced first-order system matrix for the Magnus kernels.

    mass (g, n, n), damping (g, n, n, Pc), stiffness (g, n, n, Pk) at g points, the last
    axis holding the coefficients of powers of omega. Returns terms (max(Pc, Pk), g, 2n, 2n)
    with ``A = sum_p omega^p terms[p]`` the matrix of y' = A y for y = (a q, q'), and the
    balancing scale a = sqrt(max ||M^-1 K_0||_inf) (1/s), which brings the stiff blocks to
    the same size (a similarity: the transition matrix of (q, q') is D^-1 Phi D,
    D = diag(a I, I), with the same eigenvalues)."""
    terms, a = kernel.balanced_terms(*(np.ascontiguousarray(X, dtype=float) for X in (mass, damping, stiffness)), 0.0)
    return terms, float(a)


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


def sweep_terms(model) -> np.ndarray:
    """Magnus system-matrix terms (P, 2 g, 2n, 2n) of an OmegaSplitModel at the Gauss
    angles of :func:`magnus_steps` (built once per model for the stability method "magnus")."""
    theta = gauss_angles(magnus_steps(model.samples))
    return magnus_terms(*StackedSpectra(*model._power_spectra[:3]).at(theta))[0]


def sweep_exponents(terms: np.ndarray, w: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Magnus monodromy exponents (S, 2n) at speeds w (S,) rad/s from :func:`sweep_terms`
    (one kernel call) and the reason per speed (S,) where they are not determined (NaN)."""
    exps = np.full((w.size, 2 * n), np.nan + 0j)
    message = np.full(w.size, "", dtype=object)
    Phi = np.empty((w.size, 2 * n, 2 * n))
    magnus_monodromies(terms, w, Phi)
    finite = np.isfinite(Phi).all(axis=(1, 2))
    exps[finite] = monodromy_exponent_array(Phi[finite], w[finite])
    for i in np.nonzero(~finite)[0]:
        message[i] = (f"the Magnus monodromy matrix at omega = {w[i]:.6g} rad/s is not finite; use "
                      "method='monodromy' (adaptive steps) or check the model's coefficients")
    for i in np.nonzero(finite & np.isnan(exps).any(axis=1))[0]:
        message[i] = (f"the Magnus monodromy matrix at omega = {w[i]:.6g} rad/s is singular: a mode decays "
                      "by more than 1e-308 in one period, so its exponent is not determined; use Hill's "
                      "method (method='dense' or 'sparse') or check the model's damping")
    return exps, message


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
        terms = np.abs(X).reshape(X.shape[0], n, n, -1)
        mag = terms[..., 0].copy()
        for p in range(1, terms.shape[-1]):  # elementwise (a reduction over a short last axis is slow)
            np.maximum(mag, terms[..., p], out=mag)
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
    speed's budget (and N <= LARGEST; rungs above :meth:`kept_steps` build their terms
    block by block).

    Each speed climbs its own rungs, so its result does not depend on the other speeds
    of the call. First rungs and orders, per speed: the first rung is START / 2 steps, or
    the first rung whose balanced generator size scale * span / (omega N) is at most
    FIRST_RHO (:meth:`first_rungs`: coarser rungs do not resolve the stiff modes of
    element models and cost the most squarings), at most FIRST_MAX, halved while the
    generator at the halved rung is at most CLEAN_RHO, down to CLEAN_MIN. A speed whose
    first rung stays at FIRST_MAX (its generator at FIRST_MAX / 2 steps above CLEAN_RHO,
    where errors were erratic) needs two successive comparisons within tolerance and
    claims the larger of their estimates. With both orders, a speed whose first rung has
    at least STIFF steps takes order 4 (on the stiff slider-crank its error is smaller
    than order 6's at the same steps), the others order 6 (:meth:`orders_at`).

    When the coefficients have a half-period symmetry (:func:`half_period_signs`), the
    steps cover half a period and the monodromy is ``(P Phi(T/2))^2``: the same step
    length at half the cost.
    """

    START = {4: 32, 6: 8}  # fine steps of the first comparison, at the least
    LARGEST = 4096  # steps
    STIFF = 16  # first-rung steps from which "both orders" takes order 4
    FIRST_RHO = 32.0  # largest balanced generator size scale * span / (omega steps) of a first rung
    # Most steps of a first rung: FIRST_MAX, halved while the generator at the halved rung
    # is at most CLEAN_RHO, down to CLEAN_MIN. On the slider-crank with 2-16 rod elements
    # (generators of 11-22 ... 707-1413 at 32 steps over 150-300 rad/s) the log|mu| errors
    # of order 4 against 2048 steps fall cleanly from 32 steps (2.4e-7-8.3e-6 at 32,
    # 8e-10-7.6e-8 at 64, 2e-10-2.8e-9 at 128; at 16 steps 3e-6-2.9e-4), so they are
    # compared from 32 steps; with 32 elements (1413-2827 at 64 steps) they are erratic up
    # to 512 steps (3.4e-7 at 32, 3.8e-6 at 64, 8.5e-8 at 128, 4.7e-7 at 256, 5.9e-8 at
    # 512), so its first comparison starts at 128.
    FIRST_MAX = 128
    CLEAN_RHO = 1024.0
    CLEAN_MIN = 32
    TERMS_ENTRIES = 4e7  # most entries of a rung's terms kept for all speeds (320 MB): kept_steps

    def __init__(self, mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, order: int | None = None):
        if order not in (4, 6, None):
            raise InputError(f"the Magnus ladder has order 4 or 6 (or None: both), got {order!r}")
        self.orders = (6, 4) if order is None else (order,)
        self.spectra = (mass, damping, stiffness)
        self.n = mass.shape[1]
        self.powers = (damping.shape[-1], stiffness.shape[-1])  # Pc, Pk: omega-power terms of C and K
        # the three spectra stacked as real cosine/sine rows (the kernel's input)
        self._rows = np.ascontiguousarray(StackedSpectra(*self.spectra).rows)
        self.signs = half_period_signs(mass, damping, stiffness)
        self.span = 2 * np.pi if self.signs is None else np.pi  # angle the steps cover, rad
        self._cache = kernel.new_terms_cache()  # rung terms, built as the climbs first need them
        self.scale = self.terms(self.START[self.orders[0]], self.orders[0])[1]

    def terms(self, steps: int, order: int = 6) -> tuple[np.ndarray, float]:
        """Terms (P, points steps, 2n, 2n) of the balanced system matrix at the Gauss angles
        of ``steps`` steps of ``order`` over the span, and the balancing scale (1/s); over
        half a period, term p is divided by 2^p so that the kernel, given twice the speed,
        takes steps of span / (omega steps) with the right matrix."""
        terms, a = kernel.rung_terms(self._rows, self.n, *self.powers, int(steps), order // 2, self.span,
                                     self.signs is not None, 0, int(steps), 0.0)
        return terms, float(a)

    def config(self) -> np.ndarray:
        """The ladder's settings as the kernel's config array
        (:mod:`periodyn.kernels.solvers.magnus_ladder`)."""
        c = np.empty(kernel.CONFIG_SIZE)
        c[kernel.CFG_SCALE], c[kernel.CFG_SPAN] = self.scale, self.span
        c[kernel.CFG_START4], c[kernel.CFG_START6], c[kernel.CFG_STIFF] = self.START[4], self.START[6], self.STIFF
        c[kernel.CFG_FIRST_RHO], c[kernel.CFG_FIRST_MAX] = self.FIRST_RHO, self.FIRST_MAX
        c[kernel.CFG_KEPT4], c[kernel.CFG_KEPT6] = self.kept_steps(4), self.kept_steps(6)
        c[kernel.CFG_LARGEST] = self.LARGEST
        c[kernel.CFG_TOL], c[kernel.CFG_FLOOR] = STABILITY_TOL, ERROR_FLOOR
        c[kernel.CFG_ORDERS] = 0 if len(self.orders) == 2 else self.orders[0]
        c[kernel.CFG_CLEAN_RHO], c[kernel.CFG_CLEAN_MIN] = self.CLEAN_RHO, self.CLEAN_MIN
        return c

    def cost(self, omegas: np.ndarray, steps, order: int = 6) -> np.ndarray:
        """Estimated seconds (S,) of one monodromy with ``steps`` steps of ``order`` at
        speeds omegas: the squarings of the exponentials follow the balanced generator's
        size, scale * span / (omega steps)."""
        w = np.atleast_1d(np.asarray(omegas, float))
        out = np.empty(w.size)
        kernel.rung_costs(self.config(), w, np.broadcast_to(np.asarray(steps, float), w.shape).copy(), order,
                          2 * self.n, out)
        return out

    def first_rungs(self, omegas: np.ndarray, order: int = 6) -> np.ndarray:
        """Steps (S,) of a speed's first rung: START / 2, or more where the balanced step
        generator would exceed FIRST_RHO, up to FIRST_MAX (halved while the generator at
        the halved rung is at most CLEAN_RHO, down to CLEAN_MIN)."""
        config = self.config()
        return np.array([kernel.first_rung(config, w, order) for w in np.atleast_1d(np.asarray(omegas, float))],
                        dtype=np.int64)

    def kept_steps(self, order: int) -> int:
        """Most steps of a rung of ``order`` whose terms are kept for all speeds: LARGEST,
        or fewer (a power of 2) where the rung's terms would exceed TERMS_ENTRIES; larger
        rungs build their terms block by block for each speed."""
        per_step = (order // 2) * (2 * self.n) ** 2 * max(self.powers)
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
        w = np.atleast_1d(w)
        order, first, cost = np.empty(w.size, np.int64), np.empty(w.size, np.int64), np.empty(w.size)
        kernel.plan(self.config(), w, 2 * self.n, order, first, cost)
        return order, first, cost

    def _signs(self) -> np.ndarray:
        return np.zeros(0) if self.signs is None else np.asarray(self.signs, float)

    def _moduli(self, omegas: np.ndarray, steps: int, order: int) -> tuple[np.ndarray, np.ndarray]:
        """Exponents (S, 2n) and sorted multiplier moduli (S, 2n) with ``steps`` steps
        (NaN where the monodromy matrix is not finite)."""
        d = 2 * self.n
        terms, signs = self.terms(steps, order)[0], self._signs()
        exps, mod, Phi = np.empty((omegas.size, d), complex), np.empty((omegas.size, d)), np.empty((d, d))
        A = np.empty(terms.shape[1:])
        for i, w in enumerate(omegas):
            kernel.rung_moduli(terms, float(w), order // 2, signs, A, Phi, exps[i], mod[i])
        return exps, mod

    def solve(self, omegas, budget) -> MagnusEstimate:
        """Exponents at speeds omegas (S,) rad/s, each speed doubling its steps while the
        spent estimated cost stays within budget (S,) s (one kernel call,
        :func:`periodyn.kernels.solvers.magnus_ladder.ladder_climb`)."""
        w = np.ascontiguousarray(omegas, dtype=float).reshape(-1)
        budget = np.ascontiguousarray(np.broadcast_to(np.asarray(budget, float), w.shape))
        return MagnusEstimate(*kernel.ladder_climb(self._rows, self.n, *self.powers, self._signs(), self.config(),
                                                   self._cache, w, budget))
