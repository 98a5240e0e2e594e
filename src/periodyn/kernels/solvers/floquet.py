"""Kernels of the Floquet stability analysis.

* ``select_clusters`` / ``select_clusters_batch``: one representative per exponent
  cluster from Hill eigenpairs (the eigenvector-centred criterion of Lazarus & Thomas
  2010, with the duplicate test of :mod:`periodyn.stability.hill`).
* ``magnus_product`` / ``magnus_monodromies``: the 4th-order Magnus integrator with two
  Gauss points per step, ``Phi <- exp(h/2 (A1 + A2) + sqrt(3)/12 h^2 [A2, A1]) Phi``,
  for one transition or for the monodromy matrices of many speeds at once;
  ``magnus6_product`` and ``magnus_monodromies(..., points=3)``: the 6th-order Magnus
  integrator with three Gauss points per step (Blanes, Casas & Ros 2000, in the form of
  Blanes, Casas, Oteo & Ros 2009, eq. 253): with a1 = h A2, a2 = sqrt(15)/3 h (A3 - A1),
  a3 = 10/3 h (A3 - 2 A2 + A1), C1 = [a1, a2], C2 = -[a1, 2 a3 + C1] / 60,
  ``Omega = a1 + a3 / 12 + [-20 a1 - a3 + C1, a2 + C2] / 240`` (six products a step).

Matrix exponentials of the small step generators use scaling and squaring with the
degree-12 Taylor polynomial (truncation below the unit round-off) evaluated by the
Paterson-Stockmeyer scheme (5 products). From d = 16 on, a factor with at most d^2 / 8
nonzero entries (the step generators of chains and banded models) multiplies by its entries
(:mod:`periodyn.kernels.solvers.sparse_products`): the commutators of the 6th-order
generator and the powers X^2..X^4 of the exponential.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .sparse_products import commutator_either, commutator_entries, matmul_entries, sparse_entries

_TAYLOR = np.array([1.0 / np.prod(np.arange(1.0, k + 1.0)) for k in range(13)])
_MAGNUS_C = np.sqrt(3.0) / 12.0
_SQRT15_3 = np.sqrt(15.0) / 3.0
_BLAS_MIN = 16  # matrix size from which _matmul calls BLAS


@njit(cache=True)
def _matmul(A, B, out):
    """out = A @ B for square float64 matrices (out must not alias A or B).

    From d = _BLAS_MIN on, BLAS dgemm (2x at d = 16, 6x at d = 128 over the loops);
    below, columns are taken 8 at a time (then one by one) with scalar accumulators,
    which the compiler keeps in vector registers: about twice as fast as a plain triple
    loop at d = 8, the size that dominates small Magnus sweeps."""
    d = A.shape[0]
    if d >= _BLAS_MIN:
        np.dot(A, B, out)
        return
    j0 = 0
    while j0 + 8 <= d:
        for i in range(d):
            s0 = s1 = s2 = s3 = s4 = s5 = s6 = s7 = 0.0
            for k in range(d):
                a = A[i, k]
                s0 += a * B[k, j0]
                s1 += a * B[k, j0 + 1]
                s2 += a * B[k, j0 + 2]
                s3 += a * B[k, j0 + 3]
                s4 += a * B[k, j0 + 4]
                s5 += a * B[k, j0 + 5]
                s6 += a * B[k, j0 + 6]
                s7 += a * B[k, j0 + 7]
            out[i, j0] = s0
            out[i, j0 + 1] = s1
            out[i, j0 + 2] = s2
            out[i, j0 + 3] = s3
            out[i, j0 + 4] = s4
            out[i, j0 + 5] = s5
            out[i, j0 + 6] = s6
            out[i, j0 + 7] = s7
        j0 += 8
    for j in range(j0, d):
        for i in range(d):
            s = 0.0
            for k in range(d):
                s += A[i, k] * B[k, j]
            out[i, j] = s


@njit(cache=True)
def _norm1(X):
    """Largest absolute column sum of a square matrix."""
    norm = 0.0
    for j in range(X.shape[0]):
        col = 0.0
        for i in range(X.shape[0]):
            col += abs(X[i, j])
        norm = max(norm, col)
    return norm


@njit(cache=True)
def _expm(X, out, w):
    """out = exp(X) for a small square float64 matrix; w: scratch (6, d, d).

    The squarings s are the fewest for which the first neglected Taylor term is below
    the unit round-off, bounded by ||X^13|| <= ||X^4||^3 ||X|| of the scaled matrix
    (X^2, X^4 are formed before scaling and rescaled exactly by powers of two; the
    powers of a sparse X (d >= _BLAS_MIN) from its nonzero entries): for
    the oscillatory step generators ||X^4||^(1/4) is near the spectral radius, well
    below ||X||, so this saves squarings over a plain norm test. out is NaN where ||X^4||
    overflows (the caller reports a non-finite monodromy matrix)."""
    d = X.shape[0]
    X1, X2, X3, X4, T, tmp = w[0], w[1], w[2], w[3], w[4], w[5]
    m = d * d // 8 if d >= _BLAS_MIN else 0  # X sparse: X^2, X^3, X^4 = X X^3 from its entries
    rows, cols, vals = np.empty(m, np.int64), np.empty(m, np.int64), np.empty(m)
    count = sparse_entries(X, rows, cols, vals) if m > 0 else -1
    if count < 0:
        _matmul(X, X, X2)
        _matmul(X2, X2, X4)
    else:
        matmul_entries(rows, cols, vals, count, 1.0, X, X2)
        matmul_entries(rows, cols, vals, count, 1.0, X2, X3)
        matmul_entries(rows, cols, vals, count, 1.0, X3, X4)
    n1, n4 = _norm1(X), _norm1(X4)
    if not (np.isfinite(n1) and np.isfinite(n4)):  # X^4 overflows: no squaring count resolves it
        out[:] = np.nan
        return
    squarings = 0
    while n4**3 * n1 > 6.2e9 * 1.1e-16 or n1 > 4.0:  # 13! u; n1 keeps the neglected tail geometric
        n1 *= 0.5
        n4 *= 0.0625
        squarings += 1
    s1 = 0.5**squarings
    s2 = s1 * s1
    s4 = s2 * s2
    for i in range(d):
        for j in range(d):
            X1[i, j] = X[i, j] * s1
            X2[i, j] *= s2
            X4[i, j] *= s4
    if count < 0:
        _matmul(X2, X1, X3)
    else:
        X3 *= s1 * s2
    c = _TAYLOR
    # p = B0 + X4 (B1 + X4 (B2 + c12 X4)), B_j = c_4j I + c_4j+1 X + c_4j+2 X^2 + c_4j+3 X^3
    for i in range(d):
        for j in range(d):
            T[i, j] = c[9] * X1[i, j] + c[10] * X2[i, j] + c[11] * X3[i, j] + c[12] * X4[i, j]
        T[i, i] += c[8]
    _matmul(X4, T, out)
    for i in range(d):
        for j in range(d):
            T[i, j] = out[i, j] + c[5] * X1[i, j] + c[6] * X2[i, j] + c[7] * X3[i, j]
        T[i, i] += c[4]
    _matmul(X4, T, out)
    for i in range(d):
        for j in range(d):
            out[i, j] += c[1] * X1[i, j] + c[2] * X2[i, j] + c[3] * X3[i, j]
        out[i, i] += c[0]
    for k in range(squarings):  # ping-pong between out and tmp, ending in out
        if k % 2 == 0:
            _matmul(out, out, tmp)
        else:
            _matmul(tmp, tmp, out)
    if squarings % 2 == 1:
        out[:, :] = tmp


@njit(cache=True)
def _generator4(A, step, h, G, w):
    """G = h/2 (A1 + A2) + sqrt(3)/12 h^2 [A2, A1], the 4th-order Magnus generator of
    step ``step`` from the two Gauss-point matrices A[2 step], A[2 step + 1]; w: scratch
    (>= 2, d, d)."""
    A1, A2 = A[2 * step], A[2 * step + 1]
    P, Q = w[0], w[1]
    _matmul(A2, A1, P)
    _matmul(A1, A2, Q)
    c = _MAGNUS_C * h * h
    for i in range(A1.shape[0]):
        for j in range(A1.shape[0]):
            G[i, j] = 0.5 * h * (A1[i, j] + A2[i, j]) + c * (P[i, j] - Q[i, j])


@njit(cache=True)
def _generator6(A, step, h, G, w):
    """G = the 6th-order Magnus generator (module docstring) of step ``step`` from the
    three Gauss-point matrices A[3 step .. 3 step + 2]; w: scratch (>= 6, d, d)."""
    A1, A2, A3 = A[3 * step], A[3 * step + 1], A[3 * step + 2]
    a1, a2, a3, C, X, Y = w[0], w[1], w[2], w[3], w[4], w[5]
    tmp = G  # G is written last
    d = A1.shape[0]
    for i in range(d):
        for j in range(d):
            a1[i, j] = h * A2[i, j]
            a2[i, j] = _SQRT15_3 * h * (A3[i, j] - A1[i, j])
            a3[i, j] = (10.0 / 3.0) * h * (A3[i, j] - 2.0 * A2[i, j] + A1[i, j])
    _commutator_sparse(a1, a2, C, tmp)  # C1 (a2 is zero where A does not vary over the step)
    for i in range(d):
        for j in range(d):
            X[i, j] = 2.0 * a3[i, j] + C[i, j]
    if not commutator_either(a1, X, Y, _BLAS_MIN):  # -60 C2 (the generator is often sparse)
        _commutator(a1, X, Y, tmp)
    for i in range(d):
        for j in range(d):
            X[i, j] = -20.0 * a1[i, j] - a3[i, j] + C[i, j]
            Y[i, j] = a2[i, j] - Y[i, j] / 60.0
    if not commutator_either(X, Y, C, _BLAS_MIN):
        _commutator(X, Y, C, tmp)
    for i in range(d):
        for j in range(d):
            G[i, j] = a1[i, j] + a3[i, j] / 12.0 + C[i, j] / 240.0


@njit(cache=True)
def _magnus_steps(A, h, phi, points):
    """Transition matrix phi (d, d) over ``A.shape[0] // points`` equal steps h (s) of
    y' = A(t) y from the system matrix at the ``points`` (2: order 4, 3: order 6) Gauss
    points of each step, A (points steps, d, d); phi(0) = I."""
    d = A.shape[1]
    w = np.empty((6, d, d))
    g = np.empty((6, d, d))
    G, E, other = np.empty((d, d)), np.empty((d, d)), np.empty((d, d))
    current = phi
    current[:, :] = 0.0
    for i in range(d):
        current[i, i] = 1.0
    steps = A.shape[0] // points
    for step in range(steps):
        if points == 3:
            _generator6(A, step, h, G, g)
        else:
            _generator4(A, step, h, G, g)
        _expm(G, E, w)
        _matmul(E, current, other)  # ping-pong between phi and a scratch matrix
        current, other = other, current
    if steps % 2 == 1:
        phi[:, :] = current


@njit(cache=True)
def _commutator(X, Y, out, tmp):
    """out = X Y - Y X (tmp: scratch)."""
    _matmul(X, Y, out)
    _matmul(Y, X, tmp)
    out -= tmp


@njit(cache=True)
def _commutator_sparse(X, S, out, tmp):
    """out = X S - S X, by the nonzero entries of S when they are at most an eighth of
    them (an orbit's generator varies in few entries, and S is a difference of its
    values), else by two products; tmp: scratch."""
    d = X.shape[0]
    m = d * d // 8
    rows, cols, vals = np.empty(m, np.int64), np.empty(m, np.int64), np.empty(m)
    count = sparse_entries(S, rows, cols, vals)
    if count < 0:
        _commutator(X, S, out, tmp)
    else:
        commutator_entries(X, rows, cols, vals, count, out)


@njit(cache=True)
def magnus_product(A, h, phi):
    """Transition matrix over ``A.shape[0] // 2`` equal steps h (s) of y' = A(t) y by the
    4th-order Magnus integrator.

    A: (2 steps, d, d) float64, the system matrix at the two Gauss points of each step;
    phi: (d, d) output, the transition matrix from the start (phi(0) = I)."""
    _magnus_steps(A, h, phi, 2)


@njit(cache=True)
def magnus6_product(A, h, phi):
    """Transition matrix over ``A.shape[0] // 3`` equal steps h (s) of y' = A(t) y by the
    6th-order Magnus integrator (module docstring).

    A: (3 steps, d, d) float64, the system matrix at the three Gauss points of each step;
    phi: (d, d) output, the transition matrix from the start (phi(0) = I)."""
    _magnus_steps(A, h, phi, 3)


@njit(cache=True)
def magnus_monodromies(terms, omegas, out, points=2):
    """Monodromy matrices of y' = A(theta, omega) y, theta = omega t, at many speeds.

    terms: (P, points steps, d, d) float64 with A = sum_p omega^p terms[p] at the Gauss
    angles of equal steps over one period (periodyn.stability.magnus.gauss_angles); omegas: (S,)
    rad/s; out: (S, d, d), filled with the transition matrices over T = 2 pi / omega;
    points: 2 (4th-order Magnus) or 3 (6th order)."""
    steps = terms.shape[1] // points
    A = np.empty(terms.shape[1:])
    for s in range(omegas.shape[0]):  # parallelism is across speed chunks (sweep workers)
        w = omegas[s]
        state_matrices(terms, w, A)
        _magnus_steps(A, 2.0 * np.pi / (w * steps), out[s], points)


@njit(cache=True)
def state_matrices(terms, omega, out):
    """out (g, d, d) = sum_p omega^p terms[p] for terms (P, g, d, d)."""
    out[:] = terms[0]
    power = 1.0
    for p in range(1, terms.shape[0]):
        power *= omega
        for g in range(terms.shape[1]):
            for i in range(terms.shape[2]):
                for j in range(terms.shape[3]):
                    out[g, i, j] += power * terms[p, g, i, j]


@njit(cache=True)
def select_clusters(lam, X, omega, m, n, count, out_exponents, out_centroid, out_edge):
    """One representative per exponent cluster from Hill eigenpairs; returns how many
    were found (<= count).

    lam: (k,) complex eigenvalues; X: ((2m+1) n, k) complex displacement parts of their
    eigenvectors, harmonic-major (l = -m..m). Candidates are visited by increasing
    |centroid| of their harmonic energy. A candidate belongs to an accepted cluster when
    its eigenvalue differs from the accepted one by j i omega (to 1e-7 of |lambda| + omega
    for j != 0; to 1e-10 for j = 0, the same eigenvalue found twice) and its normalized
    eigenvector lies within 0.5 of the span of the accepted vectors shifted by j
    harmonics. An accepted candidate with centroid c stands for lambda + i omega rint(c).
    Fills out_exponents, out_centroid, out_edge (count,) (edge: energy fraction in |l| = m).
    """
    k = lam.shape[0]
    nh = 2 * m + 1
    size = nh * n
    centroid = np.empty(k)
    edge = np.empty(k)
    for j in range(k):
        total = 0.0
        weighted = 0.0
        outer = 0.0
        for h in range(nh):
            e = 0.0
            for c in range(n):
                v = X[h * n + c, j]
                e += v.real * v.real + v.imag * v.imag
            total += e
            weighted += (h - m) * e
            if h == 0 or h == nh - 1:
                outer += e
        centroid[j] = weighted / total
        edge[j] = outer / total if m > 0 else 1.0
    order = np.argsort(np.abs(centroid), kind="mergesort")
    raw = np.empty(count, dtype=np.complex128)
    accepted = np.empty((count, size), dtype=np.complex128)
    basis = np.empty((count, size), dtype=np.complex128)
    x = np.empty(size, dtype=np.complex128)
    u = np.empty(size, dtype=np.complex128)
    found = 0
    for idx in order:
        if found == count:
            break
        norm = 0.0
        for r in range(size):
            norm += abs(X[r, idx]) ** 2
        norm = np.sqrt(norm)
        for r in range(size):
            x[r] = X[r, idx] / norm
        span = 0
        for a in range(found):
            d = lam[idx] - raw[a]
            j = int(np.rint(d.imag / omega))
            tol = 1e-7 if j != 0 else 1e-10
            if abs(d - 1j * omega * j) > tol * (abs(raw[a]) + omega):
                continue
            # member lambda_a + i j omega has u[l] = accepted_a[l + j] (zero outside)
            for r in range(size):
                src = r + j * n
                u[r] = accepted[a, src] if 0 <= src < size else 0.0
            for b in range(span):  # modified Gram-Schmidt against the span so far
                proj = np.vdot(basis[b], u)
                for r in range(size):
                    u[r] -= proj * basis[b, r]
            un = np.linalg.norm(u)
            if un > 1e-12:
                for r in range(size):
                    basis[span, r] = u[r] / un
                span += 1
        if span > 0:
            for r in range(size):
                u[r] = x[r]
            for b in range(span):
                proj = np.vdot(basis[b], u)
                for r in range(size):
                    u[r] -= proj * basis[b, r]
            if np.linalg.norm(u) < 0.5:
                continue
        out_exponents[found] = lam[idx] + 1j * omega * np.rint(centroid[idx])
        out_centroid[found] = centroid[idx]
        out_edge[found] = edge[idx]
        raw[found] = lam[idx]
        accepted[found] = x
        found += 1
    return found


@njit(cache=True)
def select_clusters_batch(lam, X, omegas, m, n, count, out_exponents, out_centroid, out_edge, out_found):
    """:func:`select_clusters` for S speeds: lam (S, k), X (S, (2m+1) n, k), omegas (S,);
    outputs (S, count) and out_found (S,) int64."""
    for s in range(omegas.shape[0]):
        out_found[s] = select_clusters(lam[s], X[s], omegas[s], m, n, count, out_exponents[s], out_centroid[s],
                                       out_edge[s])
