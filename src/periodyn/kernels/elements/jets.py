"""Third-order multivariate Taylor jets: the one derivative strategy of the spatial
element families.

Why one strategy. An element's kinematics need its deformation modes D and their first,
second and third derivatives with respect to the element's local nodal coordinates (the
third enter the second derivatives of the transfer function). The planar families get
them from a 2-D complex-number identity (``planar_geometry``), which has no spatial
analogue; hand-written spatial third derivatives of chords, rotation matrices and angles
are long and fragile. A jet carries a quantity together with its exact gradient, Hessian
and third-derivative tensor through every arithmetic step (forward mode, Leibniz and
Faa di Bruno rules to third order), so each element is written once, as its formula, and
its derivatives are exact to round-off with no step size. The price is O(n^3) per product
for n local coordinates (n = 14 for a spatial beam: ~2.7e3 entries per jet); it is paid
once per model sample because the linearization splits into omega-polynomials computed
once, so no spatial family has a reason to choose another strategy.

Layout. A jet over n coordinates is one flat float64 array of ``size(n) = 1 + n + n^2 + n^3``
entries: value, gradient (n,), Hessian (n,n), third derivatives (n,n,n), all C order;
:func:`parts` returns the four views. Arrays of jets put the jet last (a 3-vector of jets
is (3, size(n)), a 3x3 matrix (3, 3, size(n))). The Hessian and third derivatives are
symmetric in their indices; products and compositions compute each distinct third-order
entry once and rely on that (build jets only with these operations). Every operation
writes a caller-allocated ``out``; unless a docstring says otherwise ``out`` may be one of
the inputs (entries are written from the third order down, each reading only its own and
lower orders).
"""

import numpy as np
from numba import njit


@njit(cache=True, inline="always")  # its callers pass literal ints: one kernel each otherwise
def size(n):
    """Entries of one jet over n coordinates."""
    return 1 + n + n * n + n * n * n


@njit(cache=True)
def dim(J):
    """Number of coordinates n of the jet J (1-D, size(n) entries)."""
    m = J.shape[0]
    n = 0
    while size(n) < m:
        n += 1
    return n


@njit(cache=True)
def parts(J):
    """Views (value (1,), gradient (n,), Hessian (n,n), third (n,n,n)) of the jet J."""
    n = dim(J)
    o2 = 1 + n
    o3 = o2 + n * n
    return J[0:1], J[1:o2], J[o2:o3].reshape((n, n)), J[o3:o3 + n * n * n].reshape((n, n, n))


@njit(cache=True)
def constant(c, out):
    """out = c (all derivatives zero)."""
    out[:] = 0.0
    out[0] = c


@njit(cache=True)
def seed(value, i, out):
    """out = the coordinate x_i with value ``value``: gradient e_i, higher orders zero."""
    out[:] = 0.0
    out[0] = value
    out[1 + i] = 1.0


@njit(cache=True)
def embed(a, index, out):
    """Lift a jet a over k coordinates into out over n coordinates: coordinate j of a is
    coordinate ``index[j]`` of out (index (k,) int, distinct); entries of out that a does not
    reach are zero. out must not be a."""
    k = index.shape[0]
    _, ag, aH, aT = parts(a)
    out[:] = 0.0
    out[0] = a[0]
    _, og, oH, oT = parts(out)
    for i in range(k):
        og[index[i]] = ag[i]
        for j in range(k):
            oH[index[i], index[j]] = aH[i, j]
            for m in range(k):
                oT[index[i], index[j], index[m]] = aT[i, j, m]


@njit(cache=True)
def lincomb(alpha, a, beta, b, out):
    """out = alpha a + beta b (alpha, beta floats)."""
    for i in range(out.shape[0]):
        out[i] = alpha * a[i] + beta * b[i]


@njit(cache=True)
def add(a, b, out):
    """out = a + b."""
    lincomb(1.0, a, 1.0, b, out)


@njit(cache=True)
def sub(a, b, out):
    """out = a - b."""
    lincomb(1.0, a, -1.0, b, out)


@njit(cache=True)
def scale(a, s, out):
    """out = s a (s a float)."""
    for i in range(out.shape[0]):
        out[i] = s * a[i]


@njit(cache=True)
def _put3(T, i, j, k, t):
    """Write t to the six permutations of the symmetric third-order entry (i, j, k)."""
    T[i, j, k] = t
    T[i, k, j] = t
    T[j, i, k] = t
    T[j, k, i] = t
    T[k, i, j] = t
    T[k, j, i] = t


@njit(cache=True)
def mul(a, b, out):
    """out = a b by the Leibniz rule to third order."""
    n = dim(a)
    av, ag, aH, aT = parts(a)
    bv, bg, bH, bT = parts(b)
    ov, og, oH, oT = parts(out)
    a0 = av[0]
    b0 = bv[0]
    for i in range(n):
        for j in range(i, n):
            aij = aH[i, j]
            bij = bH[i, j]
            for k in range(j, n):
                t = (aT[i, j, k] * b0 + a0 * bT[i, j, k]
                     + aij * bg[k] + aH[i, k] * bg[j] + aH[j, k] * bg[i]
                     + ag[i] * bH[j, k] + ag[j] * bH[i, k] + ag[k] * bij)
                _put3(oT, i, j, k, t)
    for i in range(n):
        for j in range(n):
            oH[i, j] = aH[i, j] * b0 + a0 * bH[i, j] + ag[i] * bg[j] + ag[j] * bg[i]
    for i in range(n):
        og[i] = ag[i] * b0 + a0 * bg[i]
    ov[0] = a0 * b0


@njit(cache=True)
def compose(a, f0, f1, f2, f3, out):
    """out = f(a) for a univariate f given by its value and first three derivatives at
    a's value (Faa di Bruno to third order)."""
    n = dim(a)
    _, ag, aH, aT = parts(a)
    ov, og, oH, oT = parts(out)
    for i in range(n):
        for j in range(i, n):
            aij = aH[i, j]
            gij = ag[i] * ag[j]
            for k in range(j, n):
                t = (f1 * aT[i, j, k]
                     + f2 * (aij * ag[k] + aH[i, k] * ag[j] + aH[j, k] * ag[i])
                     + f3 * gij * ag[k])
                _put3(oT, i, j, k, t)
    for i in range(n):
        for j in range(n):
            oH[i, j] = f1 * aH[i, j] + f2 * ag[i] * ag[j]
    for i in range(n):
        og[i] = f1 * ag[i]
    ov[0] = f0


@njit(cache=True)
def reciprocal(a, out):
    """out = 1 / a (a's value nonzero)."""
    r = 1.0 / a[0]
    compose(a, r, -r * r, 2.0 * r * r * r, -6.0 * r * r * r * r, out)


@njit(cache=True)
def divide(a, b, out):
    """out = a / b (b's value nonzero)."""
    tmp = np.empty_like(b)
    reciprocal(b, tmp)
    mul(a, tmp, out)


@njit(cache=True)
def sqrt(a, out):
    """out = sqrt(a) (a's value positive)."""
    s = np.sqrt(a[0])
    f1 = 0.5 / s
    f2 = -0.5 * f1 / a[0]
    f3 = -1.5 * f2 / a[0]
    compose(a, s, f1, f2, f3, out)


@njit(cache=True)
def atan(a, out):
    """out = arctan(a)."""
    t = a[0]
    w = 1.0 / (1.0 + t * t)
    compose(a, np.arctan(t), w, -2.0 * t * w * w, (6.0 * t * t - 2.0) * w * w * w, out)


@njit(cache=True)
def atan2(y, x, out):
    """out = arctan2(y, x) (rad, in (-pi, pi]); y, x not both zero. The derivatives come from
    arctan of the ratio of the smaller to the larger magnitude, so they stay well scaled."""
    y0 = y[0]
    x0 = x[0]
    if abs(x0) >= abs(y0):
        divide(y, x, out)
        atan(out, out)
    else:
        divide(x, y, out)
        atan(out, out)
        scale(out, -1.0, out)
    out[0] = np.arctan2(y0, x0)


@njit(cache=True)
def dot3(u, v, out):
    """out = u . v for 3-vectors of jets u, v (3, size(n)); out may not be u or v."""
    tmp = np.empty_like(out)
    mul(u[0], v[0], out)
    for c in range(1, 3):
        mul(u[c], v[c], tmp)
        add(out, tmp, out)


@njit(cache=True)
def cross3(u, v, out):
    """out (3, size(n)) = u x v for 3-vectors of jets; out may not be u or v."""
    tmp = np.empty_like(out[0])
    for c in range(3):
        i = (c + 1) % 3
        j = (c + 2) % 3
        mul(u[i], v[j], out[c])
        mul(u[j], v[i], tmp)
        sub(out[c], tmp, out[c])


@njit(cache=True)
def matvec3(R, u, out):
    """out (3, size(n)) = R u for a 3x3 of jets R (3, 3, size(n)) and a 3-vector of jets u;
    out may not be u."""
    tmp = np.empty_like(out[0])
    for i in range(3):
        mul(R[i, 0], u[0], out[i])
        for j in range(1, 3):
            mul(R[i, j], u[j], tmp)
            add(out[i], tmp, out[i])


@njit(cache=True)
def rotation_coefficients():
    """Quadratic form of the rotation matrix of Euler parameters,
    ``R_ij(lam) = sum_kl Q[i, j, k, l] lam_k lam_l`` with Q symmetric in (k, l):
    R = (l0^2 - e.e) I + 2 e e^T + 2 l0 [e]x, lam = (l0, e), e = (l1, l2, l3)."""
    Q = np.zeros((3, 3, 4, 4))
    for i in range(3):
        Q[i, i, 0, 0] = 1.0
        for k in range(3):
            Q[i, i, 1 + k, 1 + k] -= 1.0
        for j in range(3):
            Q[i, j, 1 + i, 1 + j] += 1.0
            Q[i, j, 1 + j, 1 + i] += 1.0
    # 2 l0 [e]x: [e]x[i, j] = -eps_ijk e_k
    for i in range(3):
        j = (i + 1) % 3
        k = (i + 2) % 3
        Q[i, j, 0, 1 + k] -= 1.0
        Q[i, j, 1 + k, 0] -= 1.0
        Q[j, i, 0, 1 + k] += 1.0
        Q[j, i, 1 + k, 0] += 1.0
    return Q


@njit(cache=True)
def rotation(lam, R):
    """R (3, 3, size(n)) = rotation matrix of the Euler parameters lam (4, size(n)), any
    jets (quadratic in lam, not normalized: R is orthogonal when lam . lam = 1)."""
    Q = rotation_coefficients()
    tmp = np.empty_like(lam[0])
    for i in range(3):
        for j in range(3):
            R[i, j] = 0.0
            for k in range(4):
                for m in range(k, 4):
                    q = Q[i, j, k, m] * (1.0 if k == m else 2.0)
                    if q != 0.0:
                        mul(lam[k], lam[m], tmp)
                        lincomb(1.0, R[i, j], q, tmp, R[i, j])


@njit(cache=True, inline="always")  # its callers pass literal ints: one kernel each otherwise
def rotation_seeded(lam, offset, R):
    """R (3, 3, size(n)) = rotation matrix of Euler parameters that are the coordinates
    offset..offset+3 themselves (values lam (4,)); exploits that R is quadratic: the
    gradient is 2 Q lam, the Hessian 2 Q, the third derivatives zero."""
    Q = rotation_coefficients()
    for i in range(3):
        for j in range(3):
            Rij = R[i, j]
            Rij[:] = 0.0
            _, g, H, _ = parts(Rij)
            v = 0.0
            for k in range(4):
                for m in range(4):
                    q = Q[i, j, k, m]
                    v += q * lam[k] * lam[m]
                    g[offset + k] += 2.0 * q * lam[m]
                    H[offset + k, offset + m] = 2.0 * q
            Rij[0] = v
