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
method="monodromy": direct integration over one period (periodyn.timedomain).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla
from threadpoolctl import threadpool_limits

from .errors import ConvergenceError, InputError
from .floquet import FloquetExponents
from .hb import HillOperator, check_harmonics, hill_operator, system_spectra
from .kernels.floquet import select_clusters, select_clusters_batch
from .system import RheoLinear, Spectra

__all__ = ["FloquetExponents", "characteristic_exponents", "hill_exponents", "METHODS"]

METHODS = ("auto", "sparse", "dense", "monodromy", "magnus")
_DENSE_MAX = 600  # first-order Hill size up to which "auto" uses LAPACK


def check_method(method: str) -> str:
    if method not in METHODS:
        raise InputError(f"unknown stability method {method!r}; choose one of {METHODS}")
    return method


def select_representatives(lam: np.ndarray, X: np.ndarray, omega: float, m: int, n: int,
                           count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pick ``count`` exponents, one per cluster, from Hill eigenpairs (jitted kernel
    :func:`periodyn.kernels.floquet.select_clusters`, which documents the criterion).

    lam: (k,) eigenvalues; X: ((2m+1)n, k) displacement parts of the eigenvectors.
    Returns (centred exponents (<= count,), centroids, edge energy fractions).
    """
    exps, cents, edge = np.empty(count, complex), np.empty(count), np.empty(count)
    found = select_clusters(np.ascontiguousarray(lam, dtype=complex), np.ascontiguousarray(X, dtype=complex),
                            float(omega), m, n, count, exps, cents, edge)
    return exps[:found], cents[:found], edge[:found]


def real_form(A: np.ndarray, m: int, n: int, halves: int = 2) -> np.ndarray:
    """Unitary map of a Hill matrix of a real system to a real matrix.

    A (halves N, halves N), N = (2m+1)n, harmonic-major blocks in each half (halves=2:
    the first-order matrix on [x; lambda x], halves=1: the HB matrix), satisfies
    A = J conj(A) J, J the reversal of harmonic index l -> -l; with Q = [e_0,
    (e_l + e_-l)/sqrt2, i(e_l - e_-l)/sqrt2] (l > 0), Q^H A Q is real (LAPACK's real
    solvers are then about three times faster than the complex ones)."""
    zero, pos, neg = _real_form_indices(m, n, halves)
    r2 = np.sqrt(0.5)
    AQ = np.concatenate([A[:, zero], r2 * (A[:, pos] + A[:, neg]), 1j * r2 * (A[:, pos] - A[:, neg])], axis=1)
    return to_real_basis(AQ, m, n, halves)


def to_real_basis(v: np.ndarray, m: int, n: int, halves: int = 2) -> np.ndarray:
    """Q^H v along the first axis (see :func:`real_form`), real part; v (halves N, ...)."""
    zero, pos, neg = _real_form_indices(m, n, halves)
    r2 = np.sqrt(0.5)
    return np.concatenate([v[zero], r2 * (v[pos] + v[neg]), -1j * r2 * (v[pos] - v[neg])], axis=0).real


def from_real_basis(Wv: np.ndarray, m: int, n: int, halves: int = 2) -> np.ndarray:
    """Q Wv along the second-to-last axis: real-basis vectors (..., halves N, k) back in
    the harmonic basis, complex."""
    zero, pos, neg = _real_form_indices(m, n, halves)
    r2 = np.sqrt(0.5)
    Z = np.empty(Wv.shape, dtype=complex)
    nz, npos = zero.size, pos.size
    Z[..., zero, :] = Wv[..., :nz, :]
    plus, minus = Wv[..., nz: nz + npos, :], Wv[..., nz + npos:, :]
    Z[..., pos, :] = r2 * (plus + 1j * minus)
    Z[..., neg, :] = r2 * (plus - 1j * minus)
    return Z


@lru_cache(maxsize=64)
def _real_form_indices(m: int, n: int, halves: int = 2) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows of a Hill vector (halves blocks of (2m+1)n, harmonic-major) with l = 0, l > 0,
    and the partner row (-l, same coordinate, same half) of each l > 0 row."""
    N = (2 * m + 1) * n
    rows = np.arange(halves * N)
    half, rem = np.divmod(rows, N)
    block, coord = np.divmod(rem, n)
    l = block - m
    pos = rows[l > 0]
    partner = half[pos] * N + (m - l[pos]) * n + coord[pos]
    return rows[l == 0], pos, partner


def first_order_matrix(W: np.ndarray, V: np.ndarray, Mh_lu=None, identity: bool = True) -> np.ndarray:
    """Dense first-order Hill matrix A = [[0, I], [-Mh^-1 W, -Mh^-1 V]] (2N, 2N) complex
    (identity=False leaves out the I block, for the higher terms of a polynomial in omega)."""
    N = W.shape[0]
    if Mh_lu is not None:
        W, V = sla.lu_solve(Mh_lu, W), sla.lu_solve(Mh_lu, V)
    A = np.zeros((2 * N, 2 * N), dtype=complex)
    if identity:
        A[:N, N:] = np.eye(N)
    A[N:, :N] = -W
    A[N:, N:] = -V
    return A


def real_first_order_matrix(op: HillOperator) -> np.ndarray:
    """The first-order Hill matrix of ``op`` in the real basis of :func:`_real_form`."""
    if op.real_first_order is not None:
        return op.real_first_order
    lu = None if op.identity_mass else sla.lu_factor(op.dense(2))
    return real_form(first_order_matrix(op.dense(0), op.dense(1), lu), op.m, op.n)


def _dense_eigs(op: HillOperator):
    """All eigenpairs of the real first-order Hill matrix (LAPACK dgeev, no wrappers)."""
    R = np.asfortranarray(real_first_order_matrix(op))
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
    pat, n = op.pattern, op.n
    centre = np.nonzero((pat.k_index == 0) & (pat.l_index == 0))[0][0]
    W0, V0, M0 = (b[centre] for b in op.blocks)
    companion = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M0, W0), -np.linalg.solve(M0, V0)]])
    top = np.abs(np.linalg.eigvals(companion).imag).max()
    spacing = max(op.omega, 0.5 * op.m * op.omega)
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
    if method == "auto":
        method = "dense" if 2 * N <= _DENSE_MAX else "sparse"
    if method == "dense":
        lam, X = _dense_eigs(op)
        exps, cents, edge = select_representatives(lam, X, omega, m, n, 2 * n)
    else:
        k = min(2 * N - 2, 2 * n + max(2 * n, 12))
        while True:
            lam, X = _sparse_candidates(op, k)
            exps, cents, edge = select_representatives(lam, X, omega, m, n, 2 * n)
            if exps.size == 2 * n or k >= 2 * N - 2:
                break
            k = min(2 * N - 2, 2 * k)
    if exps.size < 2 * n:
        raise ConvergenceError(f"Hill's method with m = {m} resolved {exps.size} of {2 * n} exponent clusters at "
                               f"omega = {omega:.6g} rad/s; increase harmonics")
    order = np.lexsort((exps.imag, exps.real))
    return FloquetExponents(float(omega), exps[order], cents[order], edge[order], method)


def hill_exponents(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, omega: float,
                   harmonics: int, method: str = "auto") -> FloquetExponents:
    """Exponents of ``M(t) y'' + C(t) y' + K(t) y = 0`` from coefficient spectra.

    mass, damping, stiffness: two-sided spectra (2K+1, n, n); omega: rad/s; harmonics: m.
    method: "auto" (dense up to a first-order size of 600, else sparse), "sparse", "dense".
    """
    m = check_harmonics(harmonics)
    if check_method(method) in ("monodromy", "magnus"):
        raise InputError(f"hill_exponents works on spectra; use characteristic_exponents(system, m, method={method!r})")
    n = mass.shape[1]
    spectra = Spectra(mass, damping, stiffness, np.zeros((mass.shape[0], n)), np.zeros((1, 0, n)))
    return operator_exponents(hill_operator(spectra, omega, m), method)


def characteristic_exponents(system: RheoLinear, harmonics: int, method: str = "auto", *,
                             form: str = "direct") -> FloquetExponents:
    """Characteristic exponents of the homogeneous rheo-linear system.

    method: "sparse" (ARPACK shift-invert subset), "dense" (all Hill eigenvalues),
    "monodromy" (adaptive integration over one period, the reference), "magnus"
    (fixed-step 4th-order Magnus monodromy, fast for small stiff systems), "auto";
    ``harmonics`` is unused by the two monodromy methods.
    form: "direct" (Hill on M, C, K) or "inverse-mass" (the paper's eq. 26-27 on P, Q).
    """
    method = check_method(method)
    if method in ("monodromy", "magnus"):
        from .timedomain import monodromy_exponents

        return monodromy_exponents(system, method)
    m = check_harmonics(harmonics)
    return operator_exponents(hill_operator(system_spectra(system, m, form), system.omega, m), method)
