"""Characteristic exponents by Hill's method (Schwab & Meijaard eq. 25-27).

Substituting ``q = exp(lambda t) sum_l q_l exp(i l w t)`` into
``M(t) q'' + C(t) q' + K(t) q = 0`` gives the quadratic eigenproblem

    sum_l [lambda^2 M_{k-l} + lambda V_kl + W_kl] q_l = 0,
    V_kl = C_{k-l} + 2 i l w M_{k-l},  W_kl = K_{k-l} + i l w C_{k-l} - (l w)^2 M_{k-l},

solved in first-order form ``A z = lambda B z`` with ``A = [[0, I], [-W, -V]]``,
``B = diag(I, Mh)`` (size 2(2m+1)n). Its (2m+1)2n eigenvalues come in clusters
``lambda + i j w``; one representative per physical exponent is chosen by the
eigenvector-centred criterion of Lazarus & Thomas (2010): the members whose harmonic
energy centroid is closest to l = 0 are the accurate ones, and a member with centroid c
represents the exponent ``lambda + i w round(c)`` (the one whose eigenvector is centred).

method="sparse": ARPACK on the shift-invert operator ``(A - s B)^-1 B`` around s (near 0),
using one sparse LU of the (2m+1)n matrix ``W + s V + s^2 Mh``; more eigenvalues are
requested until 2n distinct clusters are found. method="dense": all eigenvalues of the
real form of A (LAPACK; for a chunk of speeds one stacked call, :func:`dense_exponents_batch`).
For a system (:func:`characteristic_exponents`) method="auto" takes the 6th-order Magnus
monodromy with step doubling where its error estimate certifies the verdict at less than
the estimated cost of Hill (:func:`auto_exponents`, :class:`periodyn.stability.magnus.MagnusLadder`),
else the cheaper Hill method by estimated cost (:func:`choose_method`); on an operator or
spectra alone, "auto" is that Hill choice. The choice and its reason are kept on the
result. method="monodromy": direct integration over one period (periodyn.stability.monodromy).
The blocks W, V, Mh come from
:class:`periodyn.harmonic.HarmonicOperator`.
"""

from __future__ import annotations

import dataclasses
from functools import lru_cache

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla
from threadpoolctl import threadpool_limits

from ..errors import ConvergenceError, InputError
from .floquet import STABILITY_TOL, FloquetExponents
from ..harmonic.operator import HarmonicOperator, HillOperator, check_harmonics
from ..harmonic.pattern import BlockPattern, from_real_basis
from ..kernels.solvers.floquet import select_clusters, select_clusters_batch
from ..system import RheoLinear
from .magnus import MagnusLadder
from .monodromy import monodromy_exponents

__all__ = ["FloquetExponents", "characteristic_exponents", "hill_exponents", "METHODS", "choose_method",
           "method_costs", "hill_cost", "hill_costs_many", "auto_exponents"]

METHODS = ("auto", "sparse", "dense", "monodromy", "magnus")


def check_method(method: str) -> str:
    if method not in METHODS:
        raise InputError(f"unknown stability method {method!r}; choose one of {METHODS}")
    return method


def select_representatives(lam: np.ndarray, X: np.ndarray, omega: float, m: int, n: int,
                           count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pick ``count`` exponents, one per cluster, from Hill eigenpairs (jitted kernel
    :func:`periodyn.kernels.solvers.floquet.select_clusters`, which documents the criterion).

    lam: (k,) eigenvalues; X: ((2m+1)n, k) displacement parts of the eigenvectors.
    Returns (centred exponents (<= count,), centroids, edge energy fractions).
    """
    exps, cents, edge = np.empty(count, complex), np.empty(count), np.empty(count)
    found = select_clusters(np.ascontiguousarray(lam, dtype=complex), np.ascontiguousarray(X, dtype=complex),
                            float(omega), m, n, count, exps, cents, edge)
    return exps[:found], cents[:found], edge[:found]


# Cost model of the two Hill methods, seconds on one core (fitted on the parametric chain
# and the slider-crank, m = 4..30): dense, real dgeev of size D = 2N plus the cluster
# selection; sparse, per ARPACK shift one LU of the band and the Arnoldi work on ncv vectors.
_DENSE_COST = (1.0e-9, 1.0e-4)  # s per D^3, s per call
_SHIFT_COST = (6.0e-10, 5.0e-3)  # s per flop-like unit, s per shift (ARPACK set-up)


def _arpack_k(N: int, n: int) -> int:
    """Eigenvalues first requested from ARPACK per shift."""
    return min(2 * N - 2, 2 * n + max(2 * n, 12))


def method_costs(pattern: BlockPattern) -> tuple[float, float]:
    """Estimated seconds of dense Hill and of one sparse (ARPACK) shift on ``pattern``."""
    return _costs(pattern.size, pattern.half_bandwidth, pattern.n)[:2]


@lru_cache(maxsize=256)
def _costs(N: int, u: int, n: int) -> tuple[float, float, str]:
    """method_costs and the reason for dense when it is cheaper than one shift."""
    ncv = 2 * _arpack_k(N, n) + 1
    dense = _DENSE_COST[0] * (2 * N) ** 3 + _DENSE_COST[1]
    per_shift = _SHIFT_COST[1] + _SHIFT_COST[0] * (N * u * u + 8 * N * ncv * ncv + 10 * ncv * N * u)
    return dense, per_shift, f"estimated dense {dense:.2g} s <= one ARPACK shift {per_shift:.2g} s (size {2 * N}, band {u})"


def choose_method(op: HillOperator) -> tuple[str, str]:
    """The Hill method "auto" takes at this operator, and why: the cheaper by estimated
    cost of dense (all eigenvalues, ~D^3 for D = 2N) and sparse (one shift-invert ARPACK
    run per shift; the shifts cover the mean system's frequencies in steps of m omega / 2,
    so a stiff system with few harmonics needs many)."""
    method, _, reason = hill_cost(op)
    return method, reason


def hill_cost(op: HillOperator) -> tuple[str, float, str]:
    """:func:`choose_method` with the estimated seconds of the chosen Hill method."""
    pat = op.pattern
    dense, per_shift, _ = _costs(pat.size, pat.half_bandwidth, op.n)
    return _hill_choice(pat, op.n, 0 if dense <= per_shift else _shift_frequencies(op).size)


def hill_costs_many(harmonic: HarmonicOperator, omegas: np.ndarray) -> list[tuple[str, float, str]]:
    """:func:`hill_cost` at speeds (S,) rad/s from the omega-polynomial operator, without
    evaluating the whole operator per speed: the shift count needs only its mean block."""
    pat, n = harmonic.pattern, harmonic.n
    dense, per_shift, _ = _costs(pat.size, pat.half_bandwidth, n)
    if dense <= per_shift:
        return [_hill_choice(pat, n, 0)] * len(omegas)
    W0, V0, M0 = harmonic.mean_blocks_many(omegas)
    tops = _top_frequencies(W0, V0, M0)
    return [_hill_choice(pat, n, _shift_grid(top, w, pat.m).size) for top, w in zip(tops, omegas)]


def _hill_choice(pat: BlockPattern, n: int, shifts: int) -> tuple[str, float, str]:
    """The cheaper Hill method, its estimated seconds and why, with ``shifts`` ARPACK
    shifts for sparse (0: dense costs less than one shift)."""
    dense, per_shift, cheap = _costs(pat.size, pat.half_bandwidth, n)
    if dense <= per_shift:
        return "dense", dense, cheap
    size = f"size {2 * pat.size}, band {pat.half_bandwidth}"
    method = "dense" if dense <= shifts * per_shift else "sparse"
    return (method, min(dense, shifts * per_shift),
            f"estimated dense {dense:.2g} s vs sparse {shifts * per_shift:.2g} s ({shifts} shifts, {size})")


#: Measured time of the dense Hill path (eigenvectors, basis change, cluster selection) over
#: its estimate _DENSE_COST, which counts the eigen-solve: 5-20x on the pendulum (D = 18-130)
#: and about 14x on the slider-crank (D = 200); Magnus may spend this multiple of Hill's estimate.
HILL_TIME_FACTOR = 4.0


def magnus_reason(est, i: int, hill: str, hill_seconds: float, first_cost: float) -> str:
    """Why "auto" took Magnus or Hill at speed i of a :class:`MagnusEstimate`."""
    if est.accepted[i]:
        return (f"Magnus of order {est.order[i]} with {est.steps[i]} steps: estimated error {est.error[i]:.1g} "
                f"(tolerance {STABILITY_TOL:g}) and verdict margin {est.margin[i]:.2g}; estimated {first_cost:.2g} s vs {hill} Hill "
                f"{hill_seconds:.2g} s")
    if est.steps[i] == 0:
        return f"{hill} Hill: estimated {hill_seconds:.2g} s <= Magnus {first_cost:.2g} s"
    return (f"{hill} Hill: the Magnus estimate did not certify the verdict within {HILL_TIME_FACTOR:g} x "
            f"{hill_seconds:.2g} s "
            f"({est.steps[i]} steps: error {est.error[i]:.1g}, margin {est.margin[i]:.2g})")


def auto_exponents(system: RheoLinear, op: HillOperator) -> FloquetExponents:
    """Stability method "auto" at one system: Magnus with step doubling where its error
    estimate certifies the verdict within the estimated cost of the cheaper Hill method
    (:class:`periodyn.stability.magnus.MagnusLadder`), else that Hill method; the choice and its
    reason are on the result (the same rule as the speed solver's, which builds the
    ladder once per model)."""
    hill, seconds, _ = hill_cost(op)
    S = system.spectra
    ladder = MagnusLadder(S.mass, S.damping[..., None], S.stiffness[..., None])
    w = np.array([float(system.omega)])
    est = ladder.solve(w, np.array([seconds * HILL_TIME_FACTOR]))
    reason = magnus_reason(est, 0, hill, seconds, float(est.first_cost[0]))
    if est.accepted[0]:
        nan = np.full(2 * system.n, np.nan)
        return FloquetExponents(float(system.omega), est.exponents[0], nan, nan.copy(), "magnus", reason=reason)
    return dataclasses.replace(operator_exponents(op, hill), reason=reason)


def _dense_eigs(op: HillOperator):
    """All eigenpairs of the real first-order Hill matrix (LAPACK dgeev, no wrappers)."""
    R = np.asfortranarray(op.real_first_order_matrix())
    wr, wi, _, vr, info = sla.lapack.dgeev(R, compute_vl=0, overwrite_a=1)
    if info != 0:
        raise ConvergenceError(f"LAPACK dgeev failed (info {info}) for the Hill matrix at omega = {op.omega:.6g} rad/s")
    lam = wr + 1j * wi
    vecs = vr.astype(complex)
    first = np.nonzero(wi > 0)[0]  # a conjugate pair is stored as (re, im) in columns j, j+1
    vecs[:, first] = vr[:, first] + 1j * vr[:, first + 1]
    vecs[:, first + 1] = vr[:, first] - 1j * vr[:, first + 1]
    return lam, from_real_basis(vecs, op.m, op.n)[: op.pattern.size]


def dense_exponents_batch(real_matrices: np.ndarray, omegas: np.ndarray, m: int,
                          n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hill exponents at S speeds from their real first-order Hill matrices (S, 2N, 2N)
    (N = (2m+1)n), all eigenpairs by LAPACK in one stacked call, clusters by the jitted
    selection. Returns exponents (S, 2n) complex sorted by real then imaginary part, edge
    fractions (S, 2n), and the number of clusters resolved per speed (S,) (< 2n: failed,
    the missing entries are NaN)."""
    lam, vecs = np.linalg.eig(real_matrices)
    X = np.ascontiguousarray(from_real_basis(vecs, m, n)[:, : (2 * m + 1) * n])
    S, count = omegas.shape[0], 2 * n
    exps = np.full((S, count), np.nan + 0j)
    cents, edge = np.full((S, count), np.nan), np.full((S, count), np.nan)
    found = np.zeros(S, dtype=np.int64)
    select_clusters_batch(np.ascontiguousarray(lam, dtype=complex), X, np.asarray(omegas, float), m, n, count,
                          exps, cents, edge, found)
    order = np.lexsort((exps.imag, exps.real), axis=-1)
    return np.take_along_axis(exps, order, -1), np.take_along_axis(edge, order, -1), found


def _sparse_eigs(op: HillOperator, k: int, sigma: complex):
    N = op.W.shape[0]
    lu = spla.splu((op.W + sigma * op.V + sigma**2 * op.Mh).tocsc())
    VsM = (op.V + sigma * op.Mh).tocsr()
    Mh = op.Mh.tocsr()

    def apply(z):
        z1, z2 = z[:N], z[N:]
        x = lu.solve(-(Mh @ z2) - VsM @ z1)
        return np.concatenate([x, z1 + sigma * x])

    Op = spla.LinearOperator((2 * N, 2 * N), matvec=apply, dtype=complex)
    v0 = np.ones(2 * N, dtype=complex) / np.sqrt(2 * N)
    with threadpool_limits(limits=1):  # ARPACK's small dense steps only lose to BLAS/OpenMP threads
        nu, Z = spla.eigs(Op, k=k, which="LM", v0=v0, tol=1e-13, maxiter=max(1000, 20 * N))
    return sigma + 1.0 / nu, Z[:N]


def _shift_frequencies(op: HillOperator) -> np.ndarray:
    """Imaginary parts (rad/s, >= 0) of the shift-invert centres: from 0 up to the highest
    vibration frequency of the mean system (l = 0 block), spaced m*omega/2 so that every
    exponent has a computed cluster member with centroid |c| <= m/4."""
    centre = op.pattern.centre_block
    top = _top_frequencies(*(b[centre][None] for b in op.blocks[:2]), op.blocks[2][centre])[0]
    return _shift_grid(top, op.omega, op.m)


def _top_frequencies(W0: np.ndarray, V0: np.ndarray, M0: np.ndarray) -> np.ndarray:
    """Highest vibration frequency (rad/s) of the mean systems M0 s^2 + V0 s + W0 with
    W0, V0 (S, n, n) and M0 (n, n): the largest |Im| of the companion eigenvalues, (S,)."""
    S, n = W0.shape[:2]
    companion = np.zeros((S, 2 * n, 2 * n), dtype=complex)
    companion[:, :n, n:] = np.eye(n)
    companion[:, n:, :n] = -np.linalg.solve(M0, W0)
    companion[:, n:, n:] = -np.linalg.solve(M0, V0)
    return np.abs(np.linalg.eigvals(companion).imag).max(axis=1)


def _shift_grid(top: float, omega: float, m: int) -> np.ndarray:
    """Shift centres from 0 to ``top`` rad/s spaced max(omega, m omega / 2)."""
    spacing = max(omega, 0.5 * m * omega)
    count = int(np.ceil(top / spacing)) + 1
    return np.linspace(0.0, spacing * (count - 1), count)


def _sparse_candidates(op: HillOperator, k: int):
    """Eigenpairs near each shift centre (ARPACK), with their complex conjugates (a real
    system's exponents come in pairs: (lambda, x_l) -> (conj lambda, conj x_-l))."""
    m, n, omega = op.m, op.n, op.omega
    lams, vecs = [], []
    for y in _shift_frequencies(op):
        sigma = omega * (-0.0137 + 0.0071j) + 1j * y  # off the special points 0 and i*w/2
        try:
            lam, X = _sparse_eigs(op, k, sigma)
        except spla.ArpackNoConvergence:
            raise ConvergenceError(f"ARPACK did not converge for {k} Hill eigenvalues near {sigma:.4g} at omega = "
                                   f"{omega:.6g} rad/s; try method='dense'", iterations=k) from None
        lams += [lam, np.conj(lam)]
        vecs += [X, np.conj(X.reshape(2 * m + 1, n, -1)[::-1]).reshape(X.shape)]
    return np.concatenate(lams), np.concatenate(vecs, axis=1)


def operator_exponents(op: HillOperator, method: str = "auto") -> FloquetExponents:
    """Characteristic exponents from a Hill operator (see module docstring).

    Raises ConvergenceError when 2n clusters cannot be resolved (increase harmonics) or
    ARPACK does not converge."""
    m, n, omega = op.m, op.n, op.omega
    N = op.pattern.size
    reason = ""
    if method == "auto":
        method, reason = choose_method(op)
    if method == "dense":
        lam, X = _dense_eigs(op)
        exps, cents, edge = select_representatives(lam, X, omega, m, n, 2 * n)
    else:
        k = _arpack_k(N, n)
        while True:
            lam, X = _sparse_candidates(op, k)
            exps, cents, edge = select_representatives(lam, X, omega, m, n, 2 * n)
            if exps.size == 2 * n or k >= 2 * N - 2:
                break
            k = min(2 * N - 2, 2 * k)
    if exps.size < 2 * n:
        raise ConvergenceError(f"Hill's method with m = {m} resolved {exps.size} of {2 * n} exponent clusters at "
                               f"omega = {omega:.6g} rad/s; increase harmonics")
    if not np.isfinite(exps).all():
        raise ConvergenceError(f"Hill's method ({method}) gave non-finite exponents at omega = {omega:.6g} rad/s; "
                               "check that the mass matrix is well conditioned, or use method='monodromy'")
    order = np.lexsort((exps.imag, exps.real))
    return FloquetExponents(float(omega), exps[order], cents[order], edge[order], method, reason=reason)


def hill_exponents(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, omega: float,
                   harmonics: int, method: str = "auto") -> FloquetExponents:
    """Exponents of ``M(t) y'' + C(t) y' + K(t) y = 0`` from coefficient spectra.

    mass, damping, stiffness: two-sided spectra (2K+1, n, n); omega: rad/s; harmonics: m.
    method: "auto" (the cheaper of the two by estimated cost, :func:`choose_method`),
    "sparse", "dense".
    """
    m = check_harmonics(harmonics)
    if check_method(method) in ("monodromy", "magnus"):
        raise InputError(f"hill_exponents works on spectra; use characteristic_exponents(system, m, method={method!r})")
    n = mass.shape[1]
    force = np.zeros((mass.shape[0], n, 1))
    op = HarmonicOperator.from_power_spectra(mass, damping[..., None], stiffness[..., None], force, m)
    return operator_exponents(op.at(omega), method)


def characteristic_exponents(system: RheoLinear, harmonics: int, method: str = "auto", *,
                             form: str = "direct") -> FloquetExponents:
    """Characteristic exponents of the homogeneous rheo-linear system.

    method: "sparse" (ARPACK shift-invert subset), "dense" (all Hill eigenvalues),
    "monodromy" (adaptive integration over one period, the reference), "magnus"
    (fixed-step 4th-order Magnus monodromy, fast for small stiff systems), "auto" (Magnus
    with step doubling where its error estimate certifies the verdict at less than the
    estimated cost of Hill, else dense or sparse Hill, whichever is estimated cheaper;
    see ``.method`` and ``.reason``);
    ``harmonics`` is unused by the two monodromy methods.
    form: "direct" (Hill on M, C, K) or "inverse-mass" (the paper's eq. 26-27 on P, Q).
    """
    method = check_method(method)
    if method in ("monodromy", "magnus"):
        return monodromy_exponents(system, method)
    op = HarmonicOperator.for_system(system, harmonics, form).at(system.omega)
    return auto_exponents(system, op) if method == "auto" else operator_exponents(op, method)
