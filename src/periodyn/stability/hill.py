"""Hill's method (Schwab & Meijaard eq. 25-27): the stability methods "dense" and "sparse".

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

"sparse": ARPACK on the shift-invert operator ``(A - s B)^-1 B`` around s (near 0),
using one sparse LU of the (2m+1)n matrix ``W + s V + s^2 Mh``; more eigenvalues are
requested until 2n distinct clusters are found. "dense": all eigenvalues of the
real form of A (LAPACK; for a chunk of speeds one stacked call, :func:`dense_exponents_batch`).
:func:`hill_solve` runs either on a :class:`periodyn.harmonic.HillOperator` (blocks W, V,
Mh from :class:`periodyn.harmonic.HarmonicOperator`); which one "auto" takes, and the
public entry points, are in :mod:`periodyn.stability.methods`.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla
from threadpoolctl import threadpool_limits

from ..errors import ConvergenceError
from .floquet import FloquetExponents
from ..harmonic.operator import HillOperator
from ..harmonic.pattern import from_real_basis
from ..kernels.solvers.floquet import select_clusters, select_clusters_batch

__all__ = ["FloquetExponents", "hill_solve", "dense_exponents_batch", "select_representatives", "shift_frequencies",
           "top_frequencies", "shift_grid", "arpack_k"]


def arpack_k(N: int, n: int) -> int:
    """Eigenvalues first requested from ARPACK per shift (N = (2m+1)n)."""
    return min(2 * N - 2, 2 * n + max(2 * n, 12))


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


def shift_frequencies(op: HillOperator) -> np.ndarray:
    """Imaginary parts (rad/s, >= 0) of the shift-invert centres: from 0 up to the highest
    vibration frequency of the mean system (l = 0 block), spaced m*omega/2 so that every
    exponent has a computed cluster member with centroid |c| <= m/4."""
    centre = op.pattern.centre_block
    top = top_frequencies(*(b[centre][None] for b in op.blocks[:2]), op.blocks[2][centre])[0]
    return shift_grid(top, op.omega, op.m)


def top_frequencies(W0: np.ndarray, V0: np.ndarray, M0: np.ndarray) -> np.ndarray:
    """Highest vibration frequency (rad/s) of the mean systems M0 s^2 + V0 s + W0 with
    W0, V0 (S, n, n) and M0 (n, n): the largest |Im| of the companion eigenvalues, (S,)."""
    S, n = W0.shape[:2]
    companion = np.zeros((S, 2 * n, 2 * n), dtype=complex)
    companion[:, :n, n:] = np.eye(n)
    companion[:, n:, :n] = -np.linalg.solve(M0, W0)
    companion[:, n:, n:] = -np.linalg.solve(M0, V0)
    return np.abs(np.linalg.eigvals(companion).imag).max(axis=1)


def shift_grid(top: float, omega: float, m: int) -> np.ndarray:
    """Shift centres from 0 to ``top`` rad/s spaced max(omega, m omega / 2)."""
    spacing = max(omega, 0.5 * m * omega)
    count = int(np.ceil(top / spacing)) + 1
    return np.linspace(0.0, spacing * (count - 1), count)


def _sparse_candidates(op: HillOperator, k: int):
    """Eigenpairs near each shift centre (ARPACK), with their complex conjugates (a real
    system's exponents come in pairs: (lambda, x_l) -> (conj lambda, conj x_-l))."""
    m, n, omega = op.m, op.n, op.omega
    lams, vecs = [], []
    for y in shift_frequencies(op):
        sigma = omega * (-0.0137 + 0.0071j) + 1j * y  # off the special points 0 and i*w/2
        try:
            lam, X = _sparse_eigs(op, k, sigma)
        except spla.ArpackNoConvergence:
            raise ConvergenceError(f"ARPACK did not converge for {k} Hill eigenvalues near {sigma:.4g} at omega = "
                                   f"{omega:.6g} rad/s; try method='dense'", iterations=k) from None
        lams += [lam, np.conj(lam)]
        vecs += [X, np.conj(X.reshape(2 * m + 1, n, -1)[::-1]).reshape(X.shape)]
    return np.concatenate(lams), np.concatenate(vecs, axis=1)




def hill_solve(op: HillOperator, method: str, reason: str = "") -> FloquetExponents:
    """Characteristic exponents from a Hill operator by ``method`` "dense" or "sparse"
    (module docstring); ``reason``: why that method (kept on the result).

    Raises ConvergenceError when 2n clusters cannot be resolved (increase harmonics) or
    ARPACK does not converge."""
    m, n, omega = op.m, op.n, op.omega
    N = op.pattern.size
    if method == "dense":
        lam, X = _dense_eigs(op)
        exps, cents, edge = select_representatives(lam, X, omega, m, n, 2 * n)
    else:
        k = arpack_k(N, n)
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
