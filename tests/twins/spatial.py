"""Plain-NumPy twins of the spatial beam kernels, written independently of them: derivative
tensors as whole arrays (einsum Leibniz and Faa di Bruno rules), the rotation matrix's
quadratic form built from the Rodrigues formula, angles from the closed-form partial
derivatives of atan2 (the planar chord twin), inertia assembled by einsum from Lagrange's
equations. Needs NumPy and periodyn's test helpers only (no pytest)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tests.twins.planar import chord_twin

N = 14
EPS = np.zeros((3, 3, 3))
EPS[0, 1, 2] = EPS[1, 2, 0] = EPS[2, 0, 1] = 1.0
EPS[0, 2, 1] = EPS[2, 1, 0] = EPS[1, 0, 2] = -1.0


def _sym3(a2, b1):
    """a_ij b_k + a_ik b_j + a_jk b_i for the trailing derivative indices."""
    t = np.einsum("...ij,...k->...ijk", a2, b1)
    return t + np.swapaxes(t, -1, -2) + np.moveaxis(t, -1, -3)


@dataclass
class Tay:
    """A (tensor of) function(s) of the 14 local coordinates with derivatives to third order:
    v (S), d1 (S + (n,)), d2 (S + (n, n)), d3 (S + (n, n, n))."""

    v: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    d3: np.ndarray

    def __add__(self, o):
        return Tay(self.v + o.v, self.d1 + o.d1, self.d2 + o.d2, self.d3 + o.d3)

    def __sub__(self, o):
        return Tay(self.v - o.v, self.d1 - o.d1, self.d2 - o.d2, self.d3 - o.d3)

    def scaled(self, s):
        return Tay(s * self.v, s * self.d1, s * self.d2, s * self.d3)

    def __getitem__(self, i):
        return Tay(self.v[i], self.d1[i], self.d2[i], self.d3[i])


def times(f: Tay, g: Tay) -> Tay:
    """Elementwise product (broadcast over the leading shape)."""
    fv, gv = np.asarray(f.v)[..., None], np.asarray(g.v)[..., None]
    d1 = f.d1 * gv + fv * g.d1
    d2 = (f.d2 * gv[..., None] + fv[..., None] * g.d2 + np.einsum("...i,...j->...ij", f.d1, g.d1)
          + np.einsum("...i,...j->...ij", g.d1, f.d1))
    d3 = (f.d3 * gv[..., None, None] + fv[..., None, None] * g.d3 + _sym3(f.d2, g.d1) + _sym3(g.d2, f.d1))
    return Tay(f.v * g.v, d1, d2, d3)


def dot(f: Tay, g: Tay) -> Tay:
    p = times(f, g)
    return Tay(p.v.sum(0), p.d1.sum(0), p.d2.sum(0), p.d3.sum(0))


def cross(f: Tay, g: Tay) -> Tay:
    parts = [times(f[j], g[k]).scaled(EPS[i, j, k]) for i in range(3) for j in range(3) for k in range(3)
             if EPS[i, j, k] != 0.0]
    comps = []
    for i in range(3):
        a, b = parts[2 * i], parts[2 * i + 1]
        comps.append(a + b)
    return Tay(*(np.stack([getattr(c, name) for c in comps]) for name in ("v", "d1", "d2", "d3")))


def unary(f: Tay, f0, f1, f2, f3) -> Tay:
    """g(f) for a scalar f and g given by its value and derivatives at f.v."""
    d1 = f1 * f.d1
    d2 = f1 * f.d2 + f2 * np.outer(f.d1, f.d1)
    d3 = f1 * f.d3 + f2 * _sym3(f.d2, f.d1) + f3 * np.einsum("i,j,k->ijk", f.d1, f.d1, f.d1)
    return Tay(f0, d1, d2, d3)


def sqrt(f: Tay) -> Tay:
    s = np.sqrt(f.v)
    return unary(f, s, 0.5 / s, -0.25 / s**3, 0.375 / s**5)


def recip(f: Tay) -> Tay:
    return unary(f, 1 / f.v, -1 / f.v**2, 2 / f.v**3, -6 / f.v**4)


def angle(y: Tay, x: Tay) -> Tay:
    """atan2(y, x) from the closed-form partial derivatives w.r.t. (x, y)."""
    _, val, _, (a1, a2, a3) = chord_twin(np.array([x.v, y.v]))
    Y1 = np.stack([x.d1, y.d1])
    Y2 = np.stack([x.d2, y.d2])
    Y3 = np.stack([x.d3, y.d3])
    d1 = a1 @ Y1
    d2 = np.einsum("ab,ai,bj->ij", a2, Y1, Y1) + np.einsum("a,aij->ij", a1, Y2)
    t = np.einsum("ab,aij,bk->ijk", a2, Y2, Y1)
    d3 = (np.einsum("abc,ai,bj,ck->ijk", a3, Y1, Y1, Y1) + t + t.transpose(0, 2, 1) + t.transpose(2, 1, 0)
          + np.einsum("a,aijk->ijk", a1, Y3))
    return Tay(val, d1, d2, d3)


def coordinate(xe, i) -> Tay:
    d1 = np.zeros(N)
    d1[i] = 1.0
    return Tay(xe[i], d1, np.zeros((N, N)), np.zeros((N, N, N)))


def rotation_form():
    """Q (3,3,4,4) with R_ij = Q_ijkl lam_k lam_l, from R = (l0^2 - e.e) I + 2 e e^T + 2 l0 [e]x
    written as the polarization of R(lam) = lam_0^2 I + ... sampled at basis combinations."""
    def R(lam):
        l0, e = lam[0], lam[1:]
        ex = np.array([[0, -e[2], e[1]], [e[2], 0, -e[0]], [-e[1], e[0], 0]])
        return (l0**2 - e @ e) * np.eye(3) + 2 * np.outer(e, e) + 2 * l0 * ex
    Q = np.zeros((3, 3, 4, 4))
    I4 = np.eye(4)
    for k in range(4):
        for m in range(4):
            Q[:, :, k, m] = 0.25 * (R(I4[k] + I4[m]) - R(I4[k] - I4[m]))
    return Q


Q = rotation_form()


def axes(xe, par) -> Tay:
    """Section axes t (2 nodes, 3 axes, 3 components) with derivatives (quadratic in lam)."""
    v = np.zeros((2, 3, 3))
    d1 = np.zeros((2, 3, 3, N))
    d2 = np.zeros((2, 3, 3, N, N))
    for node in range(2):
        off = 3 + 7 * node
        lam = xe[off:off + 4]
        A = par[1 + 9 * node:10 + 9 * node].reshape(3, 3)
        B = np.einsum("cjkl,aj->ackl", Q, A)      # t_a,c = B_ackl lam_k lam_l
        v[node] = np.einsum("ackl,k,l->ac", B, lam, lam)
        d1[node, :, :, off:off + 4] = 2 * np.einsum("ackl,l->ack", B, lam)
        d2[node, :, :, off:off + 4, off:off + 4] = 2 * B
    return Tay(v, d1, d2, np.zeros((2, 3, 3, N, N, N)))


def chord(xe) -> Tay:
    d1 = np.zeros((3, N))
    d1[:, 7:10] = np.eye(3)
    d1[:, 0:3] = -np.eye(3)
    return Tay(xe[7:10] - xe[0:3], d1, np.zeros((3, N, N)), np.zeros((3, N, N, N)))


def beam_deformation_twin(xe, par):
    """(D (6,), Dx, Dxx, Dxxx) of the spatial beam."""
    l0 = par[0]
    u, t = chord(xe), axes(xe, par)
    d = [[dot(t[node, k], u) for k in range(3)] for node in range(2)]
    a = [angle(d[node][1].scaled(-1.0), d[node][0]) for node in range(2)]
    b = [angle(d[node][2], d[node][0]) for node in range(2)]
    s = dot(t[0, 2], t[1, 1]) - dot(t[0, 1], t[1, 2])
    c = dot(t[0, 1], t[1, 1]) + dot(t[0, 2], t[1, 2])
    torsion = angle(s, c) + times(b[0], a[1]) - times(b[1], a[0])
    bow = Tay(0.0, np.zeros(N), np.zeros((N, N)), np.zeros((N, N, N)))
    for p, q in ((a[0], a[1]), (b[0], b[1])):
        bow = bow + times(p, p).scaled(2) - times(p, q) + times(q, q).scaled(2)
    el = sqrt(dot(u, u)) + bow.scaled(l0 / 30)
    el.v = el.v - l0
    modes = [el, torsion, a[0], a[1], b[0], b[1]]
    return tuple(np.stack([np.asarray(getattr(f, name)) for f in modes]) for name in ("v", "d1", "d2", "d3"))


def _stack(items):
    return Tay(*(np.stack([np.asarray(getattr(f, name)) for f in items]) for name in ("v", "d1", "d2", "d3")))


def _gauss(functions, order=6):
    s, w = np.polynomial.legendre.leggauss(order)
    s, w = 0.5 * (s + 1), 0.5 * w
    F = np.array([f(s) for f in functions])
    return (F * w) @ F.T, F @ w


HERMITE = (lambda s: 1 - 3 * s**2 + 2 * s**3, lambda s: 3 * s**2 - 2 * s**3,
           lambda s: s - 2 * s**2 + s**3, lambda s: -(s**2) + s**3)
SLOPES = (lambda s: 6 * s - 6 * s**2, lambda s: 1 - 4 * s + 3 * s**2, lambda s: -2 * s + 3 * s**2)


def beam_inertia_twin(xe, ve, ae, ipar, gravity):
    """(M, r, C, K) (14,14), (14,), (14,14), (14,14) of the spatial beam's inertia."""
    l0, rhoA, E, lumped = ipar[0], ipar[19], ipar[20:23], ipar[23] != 0.0
    t = axes(xe, ipar)
    u = chord(xe)
    pos = [_stack([coordinate(xe, 7 * node + c) for c in range(3)]) for node in range(2)]
    vectors = [pos[0], pos[1], t[0, 0].scaled(l0), t[1, 0].scaled(l0)]
    hm, hw = _gauss(HERMITE)
    blocks = [rhoA * l0 * hm]
    weights = [rhoA * l0 * hw]
    if lumped:
        for node in range(2):
            for k in range(3):
                vectors.append(t[node, k])
                blocks.append(np.array([[0.5 * l0 * E[k]]]))
                weights.append(np.zeros(1))
    else:
        c1 = times(u, recip(sqrt(dot(u, u))))
        w = t[0, 1] + t[1, 1]
        w = w - times(c1, dot(w, c1))
        c2 = times(w, recip(sqrt(dot(w, w))))
        frame = [c1, c2, cross(c1, c2)]
        sm = _gauss(SLOPES)[0]
        for k in range(3):
            vectors += [frame[k], t[0, k], t[1, k]]
            blocks.append(l0 * E[k] * sm)
            weights.append(np.zeros(3))
    nv = len(vectors)
    mass = np.zeros((nv, nv))
    i = 0
    for blk in blocks:
        mass[i:i + len(blk), i:i + len(blk)] = blk
        i += len(blk)
    wts = np.concatenate(weights)
    g = _stack(vectors)                     # (nv, 3) ...
    acc = np.einsum("vca,a->vc", g.d1, ae) + np.einsum("vcab,a,b->vc", g.d2, ve, ve)
    b = mass @ acc.reshape(nv, 3) - np.outer(wts, gravity)
    M = np.einsum("ij,ica,jcb->ab", mass, g.d1, g.d1)
    r = np.einsum("ica,ic->a", g.d1, b)
    C = 2 * np.einsum("ij,ica,jcbd,d->ab", mass, g.d1, g.d2, ve)
    dacc = np.einsum("jcbd,d->jcb", g.d2, ae) + np.einsum("jcbde,d,e->jcb", g.d3, ve, ve)
    K = np.einsum("icab,ic->ab", g.d2, b) + np.einsum("ij,ica,jcb->ab", mass, g.d1, dacc)
    return M, r, C, K
