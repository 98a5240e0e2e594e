"""Kernels of the certified Magnus ladder (:class:`periodyn.stability.magnus.MagnusLadder`).

* ``balanced_terms``: the terms ``A = sum_p omega^p terms[p]`` of the balanced state
  matrix of ``y' = A y``, ``y = (a q, q')``, from M, C, K at g angles.
* ``rung_terms``: those terms at the Gauss angles of a rung (``steps`` equal steps of
  2 or 3 Gauss points over the ladder's span, or a block of them) from the stacked real
  spectra ``rows`` (2K+1, width): the cosine/sine rows of M (n, n), C (n, n, Pc) and K
  (n, n, Pk) flattened in C order and placed side by side
  (:class:`periodyn.numerics.spectra.StackedSpectra`).
* ``rung_moduli`` / ``streamed_moduli``: one rung's monodromy, exponents and multiplier
  moduli at one speed, from kept terms or from terms built block by block.
* ``rung_cost`` / ``first_rung`` / ``plan``: the ladder's cost model (estimated seconds
  of a monodromy), first rungs and per-speed orders.
* ``ladder_climb``: the whole step-doubling climb of many speeds in one call (plan,
  monodromies, multipliers, error estimates, verdicts); the rule is written in the
  docstring of :class:`periodyn.stability.magnus.MagnusLadder`.

The ladder's settings travel in one float array ``config`` (indices ``CFG_*`` below) so
that a call from Python costs little more than the arithmetic of one small speed.
Floating-point errors follow NumPy (``error_model="numpy"``): 0/0 is NaN, x/0 is inf.
"""

from __future__ import annotations

import numpy as np
from numba import njit, types
from numba.np.linalg import _LAPACK
from numba.typed import List

from .floquet import _magnus_steps, _matmul, state_matrices
from ..mechanism.lu import lu_factor, lu_solve

# LAPACK dgeev through Numba's own binding (the one behind np.linalg.eigvals): all
# eigenvalues of a real matrix as (wr, wi), conjugate pairs exact, as NumPy's eigvals gives
# them (np.linalg.eigvals in Numba refuses real input with complex eigenvalues)
_DGEEV = _LAPACK().numba_ez_rgeev(types.float64)

#: Gauss nodes on [0, 1] of the 4th-order (2 points) and 6th-order (3 points) integrators
GAUSS_NODES_2 = np.array([0.5 - np.sqrt(3) / 6, 0.5 + np.sqrt(3) / 6])
GAUSS_NODES_3 = np.array([0.5 - np.sqrt(15) / 10, 0.5, 0.5 + np.sqrt(15) / 10])

# Seconds per Magnus step ~ (products + squarings) products of d x d matrices + a set-up
# (fitted on one core for d = 2..128: the jitted loops below d = 16, BLAS dgemm from there on)
_RATE_SMALL, _RATE_LARGE = 4.5e9, 1.2e10  # flop/s of one product, below / from d = 16
_STEP_SETUP = 5.0e-7  # s per step
_PRODUCTS_4, _PRODUCTS_6 = 6.0, 12.0  # products per step besides the squarings (commutators, Taylor)

# config layout (float64 array)
CFG_SCALE, CFG_SPAN, CFG_START4, CFG_START6, CFG_STIFF, CFG_FIRST_RHO, CFG_FIRST_MAX = 0, 1, 2, 3, 4, 5, 6
CFG_KEPT4, CFG_KEPT6, CFG_TOL, CFG_FLOOR, CFG_ORDERS, CFG_CLEAN_RHO, CFG_CLEAN_MIN, CFG_LARGEST = range(7, 15)
CONFIG_SIZE = 15  # CFG_ORDERS: 4 or 6 (that order only) or 0 (both, chosen per speed)
# CFG_KEPT4/6: most steps of a rung whose terms are kept in the cache (larger rungs are
# built block by block per speed: streamed_moduli); CFG_LARGEST: most steps of any rung
STREAM_BLOCK = 64  # steps whose terms a rung beyond the kept ones builds at a time (at most)
LEVELS = 16  # rungs of 1, 2, 4, ... 2^15 steps per order in a terms cache (new_terms_cache)


@njit(cache=True)
def balanced_terms(mass, damping, stiffness, scale):
    """Terms (max(Pc, Pk), g, 2n, 2n) of the balanced state matrix and the balancing
    scale: ``scale`` where positive, else a = sqrt(max ||M^-1 K_0||_inf) over the g points
    (1/s, 1 if that is 0); NaN terms at angles where the mass matrix is singular.

    mass (g, n, n), damping (g, n, n, Pc), stiffness (g, n, n, Pk) C-contiguous, the last
    axis holding the coefficients of powers of omega."""
    g, n = mass.shape[0], mass.shape[1]
    Pc, Pk = damping.shape[3], stiffness.shape[3]
    P = max(Pc, Pk)
    MinvC = np.empty((g, n, n * Pc))
    MinvK = np.empty((g, n, n * Pk))
    rhs = np.empty((n, n * (Pc + Pk)))
    LU, piv = np.empty((n, n)), np.empty(n, np.int64)
    top = 0.0
    for i in range(g):
        LU[:, :] = mass[i]
        rhs[:, : n * Pc] = damping[i].reshape(n, n * Pc)
        rhs[:, n * Pc:] = stiffness[i].reshape(n, n * Pk)
        if lu_factor(LU, piv) != 0:  # singular mass matrix: no state matrix (NaN terms)
            rhs[:, :] = np.nan
        else:
            lu_solve(LU, piv, rhs)
        MinvC[i] = rhs[:, : n * Pc]
        MinvK[i] = rhs[:, n * Pc:]
        for r in range(n):
            row = 0.0
            for c in range(n):
                row += abs(MinvK[i, r, c * Pk])
            top = max(top, row)
    a = scale if scale > 0 else (np.sqrt(top) if top > 0 else 1.0)
    terms = np.zeros((P, g, 2 * n, 2 * n))
    for i in range(g):
        for r in range(n):
            terms[0, i, r, n + r] = a
            for c in range(n):
                for p in range(Pk):
                    terms[p, i, n + r, c] = -MinvK[i, r, c * Pk + p] / a
                for p in range(Pc):
                    terms[p, i, n + r, n + c] = -MinvC[i, r, c * Pc + p]
    return terms, a


@njit(cache=True)
def rung_terms(rows, n, Pc, Pk, steps, points, span, halve, first, count, scale):
    """:func:`balanced_terms` (with ``scale``) at the ``points`` Gauss angles of steps
    first ... first + count - 1 of ``steps`` equal steps over [0, span] from the stacked
    rows (2K+1, width) (module docstring); with ``halve`` (half-period symmetric
    coefficients: the kernel is given twice the speed) term p is divided by 2^p."""
    K = (rows.shape[0] - 1) // 2
    nodes = GAUSS_NODES_3 if points == 3 else GAUSS_NODES_2
    g = count * points
    basis = np.empty((g, 2 * K + 1))
    for s in range(count):
        for j in range(points):
            theta = span * ((first + s + nodes[j]) / steps)
            row = basis[s * points + j]
            row[0] = 1.0
            c1, s1 = np.cos(theta), np.sin(theta)
            ck, sk = 1.0, 0.0
            for k in range(1, K + 1):  # cos k theta, sin k theta by angle addition (error ~ k eps)
                ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
                row[2 * k - 1] = ck
                row[2 * k] = sk
    values = np.dot(basis, rows)
    nm, nc = n * n, n * n * Pc
    mass = np.ascontiguousarray(values[:, :nm]).reshape(g, n, n)
    damping = np.ascontiguousarray(values[:, nm: nm + nc]).reshape(g, n, n, Pc)
    stiffness = np.ascontiguousarray(values[:, nm + nc:]).reshape(g, n, n, Pk)
    terms, a = balanced_terms(mass, damping, stiffness, scale)
    if halve:
        factor = 1.0
        for p in range(1, terms.shape[0]):
            factor *= 0.5
            terms[p] *= factor
    return terms, a


@njit(cache=True)
def new_terms_cache():
    """An empty cache of rung terms for :func:`ladder_climb`: a typed list of 2 LEVELS
    arrays (order 6, then order 4; entry ``log2(steps)`` of each), filled as rungs are
    first climbed and kept by the caller across calls (an empty array: not yet built)."""
    cache = List()
    for _ in range(2 * LEVELS):
        cache.append(np.empty((0, 0, 0, 0)))
    return cache


@njit(cache=True)
def rung_cost(scale, span, omega, steps, order, d):
    """Estimated seconds of one monodromy with ``steps`` steps of ``order`` at speed omega:
    the squarings of the exponentials follow the balanced generator's size,
    scale * span / (omega steps)."""
    rho = scale * span / (omega * steps)
    squarings = max(0.0, np.ceil(np.log2(max(rho, 1e-300) / 4.0)))
    product = 2.0 * d**3 / (_RATE_LARGE if d >= 16 else _RATE_SMALL)
    return steps * (((_PRODUCTS_6 if order == 6 else _PRODUCTS_4) + squarings) * product + _STEP_SETUP)


@njit(cache=True)
def first_rung(config, omega, order):
    """Steps of a speed's first rung of ``order``: START / 2, or more where the balanced
    step generator would exceed FIRST_RHO, up to FIRST_MAX, halved while the generator at
    the halved rung is at most CLEAN_RHO, down to CLEAN_MIN."""
    size = config[CFG_SCALE] * config[CFG_SPAN] / omega  # balanced generator size of a single step over the span
    most = config[CFG_FIRST_MAX]
    while 0.5 * most >= config[CFG_CLEAN_MIN] and size / (0.5 * most) <= config[CFG_CLEAN_RHO]:
        most *= 0.5
    rho = min(max(size / config[CFG_FIRST_RHO], 1.0), most)
    steps = 1 << int(np.ceil(np.log2(rho)))
    return max(int(config[CFG_START6 if order == 6 else CFG_START4]) // 2, steps)


@njit(cache=True)
def rung_costs(config, omegas, steps, order, d, out):
    """out (S,) = :func:`rung_cost` at speeds omegas (S,) with steps (S,)."""
    for s in range(omegas.shape[0]):
        out[s] = rung_cost(config[CFG_SCALE], config[CFG_SPAN], omegas[s], steps[s], order, d)


@njit(cache=True)
def plan(config, omegas, d, out_order, out_first, out_cost):
    """Per speed: the Magnus order (4 or 6; with both, 4 where the first rung of order 6
    has at least STIFF steps), its first rung and the estimated seconds of the first two
    rungs of a d x d monodromy; outputs (S,)."""
    both = config[CFG_ORDERS] == 0
    for s in range(omegas.shape[0]):
        w = omegas[s]
        order = 6 if both else int(config[CFG_ORDERS])
        first = first_rung(config, w, order)
        if both and first >= config[CFG_STIFF]:
            order = 4
            first = first_rung(config, w, np.int64(4))
        out_order[s], out_first[s] = order, first
        out_cost[s] = (rung_cost(config[CFG_SCALE], config[CFG_SPAN], w, first, order, d)
                       + rung_cost(config[CFG_SCALE], config[CFG_SPAN], w, 2 * first, order, d))


@njit(cache=True, error_model="numpy")
def rung_moduli(terms, omega, points, signs, A, Phi, exps, moduli):
    """One rung at one speed: the monodromy Phi (d, d) from the rung's terms (A: scratch
    of the shape of terms[0]), its exponents exps (d,) and sorted multiplier moduli (d,)
    (:func:`_multiplier_moduli`). With signs (n,) (half-period symmetry; empty: none) the
    terms span half a period and Phi = (P Phi(T/2))^2."""
    w = 2.0 * omega if signs.shape[0] > 0 else omega
    state_matrices(terms, w, A)
    _magnus_steps(A, 2.0 * np.pi / (w * (terms.shape[1] // points)), Phi, points)
    _multiplier_moduli(Phi, omega, signs, exps, moduli)


@njit(cache=True, error_model="numpy")
def streamed_moduli(rows, n, Pc, Pk, steps, points, span, scale, block, omega, signs, Phi, exps, moduli):
    """:func:`rung_moduli` for a rung of ``steps`` steps whose terms are built ``block``
    steps at a time for this speed alone, with the balancing scale ``scale`` throughout
    (rungs too large to keep: memory stays that of ``block`` steps; building the terms
    costs a few per cent of the steps for large models)."""
    d = 2 * n
    half = signs.shape[0] > 0
    w = 2.0 * omega if half else omega
    h = 2.0 * np.pi / (w * steps)
    Phi[:, :] = 0.0
    for i in range(d):
        Phi[i, i] = 1.0
    part, product = np.empty((d, d)), np.empty((d, d))
    for first in range(0, steps, block):
        count = min(block, steps - first)
        terms = rung_terms(rows, n, Pc, Pk, steps, points, span, half, first, count, scale)[0]
        A = np.empty(terms.shape[1:])
        state_matrices(terms, w, A)
        _magnus_steps(A, h, part, points)
        _matmul(part, Phi, product)
        Phi[:, :] = product
    _multiplier_moduli(Phi, omega, signs, exps, moduli)


@njit(cache=True, error_model="numpy")
def _multiplier_moduli(Phi, omega, signs, exps, moduli):
    """Exponents exps (d,) (principal values, rad/s, sorted by real then imaginary part;
    NaN when the monodromy is not finite or singular) and sorted multiplier moduli (d,)
    exp(Re lambda T) of the transition matrix Phi (d, d) over the ladder's span, which
    becomes the monodromy: Phi itself, or (P Phi)^2 with signs (n,) (half-period symmetry)."""
    d = Phi.shape[0]
    if signs.shape[0] > 0:
        n = d // 2
        for i in range(d):
            Phi[i] *= signs[i % n]
        square = np.empty((d, d))
        _matmul(Phi, Phi, square)
        Phi[:, :] = square
    exps[:] = np.nan
    moduli[:] = np.nan
    if not np.all(np.isfinite(Phi)):
        return
    mu = _eigvals(Phi)
    for i in range(d):
        if mu[i] == 0:
            return
    lam = np.log(mu) * (omega / (2.0 * np.pi))
    order = np.arange(d)
    for i in range(1, d):  # insertion sort by (real, imag)
        j = i
        while j > 0:
            a, b = lam[order[j - 1]], lam[order[j]]
            if a.real > b.real or (a.real == b.real and a.imag > b.imag):
                order[j - 1], order[j] = order[j], order[j - 1]
                j -= 1
            else:
                break
    for i in range(d):
        exps[i] = lam[order[i]]
        moduli[i] = np.exp(exps[i].real * (2.0 * np.pi / omega))
    moduli.sort()


@njit(cache=True)
def _eigvals(X):
    """Eigenvalues (d,) complex of a real square matrix by LAPACK dgeev (X is not changed)."""
    d = X.shape[0]
    a = np.empty((d, d)).T  # Fortran order, as LAPACK reads it
    a[:, :] = X
    wr, wi, dummy = np.empty(d), np.empty(d), np.empty(1)
    info = _DGEEV(ord("d"), ord("N"), ord("N"), d, a.ctypes, d, wr.ctypes, wi.ctypes, dummy.ctypes, 1,
                  dummy.ctypes, 1)
    mu = np.empty(d, np.complex128)
    for i in range(d):
        mu[i] = complex(wr[i], wi[i]) if info == 0 else np.nan
    return mu


@njit(cache=True)
def _max_nan(a, b):
    """np.maximum: NaN if either is NaN."""
    if a != a or b != b:
        return np.nan
    return a if a >= b else b


@njit(cache=True, error_model="numpy")
def ladder_climb(rows, n, Pc, Pk, signs, config, cache, omegas, budget):
    """The certified Magnus ladder at speeds omegas (S,) rad/s, each speed doubling its
    steps while the spent estimated cost stays within budget (S,) s
    (:class:`periodyn.stability.magnus.MagnusLadder`); cache: the rung terms built so far
    (:func:`new_terms_cache`), completed in place. Returns exponents (S, 2n) complex,
    accepted (S,) bool, steps (S,) int64 (0: not tried), error (S,), margin (S,), order (S,) int64
    and the estimated seconds of the first two rungs (S,)."""
    S, d = omegas.shape[0], 2 * n
    scale, span, tol, floor = config[CFG_SCALE], config[CFG_SPAN], config[CFG_TOL], config[CFG_FLOOR]
    exps = np.full((S, d), np.nan + 0j)
    accepted = np.zeros(S, np.bool_)
    used_steps = np.zeros(S, np.int64)
    error = np.full(S, np.inf)
    margin = np.full(S, np.nan)
    used_order = np.zeros(S, np.int64)
    order_of = np.zeros(S, np.int64)
    rung = np.zeros(S, np.int64)
    first_cost = np.empty(S)
    plan(config, omegas, d, order_of, rung, first_cost)
    # speeds whose first rung stays at FIRST_MAX (the generator there above CLEAN_RHO: the
    # erratic regime) are certified by two successive comparisons, the larger estimate claimed
    guarded = rung >= config[CFG_FIRST_MAX]
    Phi = np.empty((d, d))
    e_x = np.empty(d, np.complex128)
    mod = np.empty(d)
    last = np.empty((S, d))
    for order in (6, 4):
        largest = int(config[CFG_LARGEST])
        kept = int(config[CFG_KEPT6 if order == 6 else CFG_KEPT4])
        richardson = 2.0 ** (order - 1) if order == 6 else np.inf
        points = order // 2
        active = np.zeros(S, np.bool_)
        spent, pending, e_prev, err_prev = np.zeros(S), np.zeros(S), np.full(S, np.nan), np.full(S, np.nan)
        for s in range(S):
            if order_of[s] == order and first_cost[s] <= budget[s]:
                active[s] = True
                pending[s] = rung_cost(scale, span, omegas[s], rung[s], order, d)
                rung[s] = min(rung[s], largest // 2)
                last[s] = np.nan
        while active.any():
            steps = np.min(rung[active])  # no literal start value: one compiled signature per callee
            in_cache = steps <= kept
            slot = (0 if order == 6 else LEVELS) + int(np.rint(np.log2(steps)))
            if in_cache and cache[slot].shape[0] == 0:
                cache[slot] = rung_terms(rows, n, Pc, Pk, steps, points, span, signs.shape[0] > 0, np.int64(0), steps,
                                         0.0)[0]
            terms = cache[slot] if in_cache else np.empty((0, 0, 0, 0))
            A = np.empty(terms.shape[1:])
            for s in range(S):
                if not active[s] or rung[s] != steps:
                    continue
                w = omegas[s]
                spent[s] += pending[s]
                pending[s] = rung_cost(scale, span, w, 2 * steps, order, d)
                if in_cache:
                    rung_moduli(terms, w, points, signs, A, Phi, e_x, mod)
                else:
                    streamed_moduli(rows, n, Pc, Pk, steps, points, span, scale, min(kept, STREAM_BLOCK), w, signs,
                                    Phi, e_x, mod)
                top = np.log(mod[d - 1])
                spread = 0.0
                for i in range(d):
                    spread = _max_nan(spread, abs(mod[i] - last[s, i]))
                e = _max_nan(abs(top - np.log(last[s, d - 1])), spread / mod[d - 1])
                r = e_prev[s] / e
                err = 2.0 * e / (min(r, 2.0**order) - 1.0) if r >= richardson else e
                err = _max_nan(err, floor)
                two = True
                if guarded[s]:
                    both = _max_nan(err, err_prev[s])  # NaN before the second comparison
                    err_prev[s] = err
                    two = not np.isnan(both)
                    if two:
                        err = both
                mrg = abs(top - tol)
                ok = two and err <= tol * _max_nan(1.0, abs(top)) and mrg > err
                compared = not np.isnan(last[s, d - 1]) or not np.isfinite(mod[d - 1])
                if compared:
                    exps[s] = e_x
                    used_steps[s], used_order[s] = steps, order
                    error[s], margin[s], accepted[s] = err, mrg, ok
                last[s] = mod
                e_prev[s] = e
                if 2 * steps > largest or ((ok or spent[s] + pending[s] > budget[s]) and compared):
                    active[s] = False
                rung[s] = 2 * steps
    return exps, accepted, used_steps, error, margin, used_order, first_cost
