"""Truncation indicator of a harmonic-balance solution: the harmonics it leaves out.

The Galerkin projection keeps the equations of harmonics |l| <= m only. Put the solution
q_j (j = -m..m) into the full equations M q'' + C q' + K q = f with coefficient harmonics
|k| <= K: the harmonics l = m+1..m+K of the equations are not balanced, with residual

    R_l = f_l - sum_j [-(j w)^2 M_{l-j} + i j w C_{l-j} + K_{l-j}] q_j.

One step of the block-Jacobi iteration on the missing harmonics estimates them,
q_l ~ D_l^-1 R_l with D_l = -(l w)^2 M_0 + i l w C_0 + K_0 (the mean system), and the
indicator is the largest |q_l| relative to the largest kept |q_j| (max-norm over the
coordinates). Small means the m harmonics resolve the response; with constant
coefficients it is 0. A sweep records it per point (``balance_truncation``) and warns
(:class:`BalanceTruncationWarning`) where it exceeds :data:`BALANCE_TRUNCATION_TOL`.

A sweep evaluates it by :class:`SweepTruncation`: the unbalanced harmonics R_l of all
speeds by products on P = 2(m + B) + 1 angles (B the model's coefficient band; no product
harmonic aliases onto l <= m + B), O(P n^2) per speed instead of the O(B (B + m) n^2)
harmonic convolution and the O(B n^2) evaluation of every coefficient harmonic at omega.
The coefficients' harmonics carry rounding noise (1e-14 to 3e-13 of a term's largest entry,
the kinematic Newton tolerance, flat over the harmonics): the band ends where the harmonics
reach FLOOR times each term's noise floor, and a term whose harmonics are all noise enters
the products by its mean only (in D_l), not by its noise. Of the harmonics l it solves D_l
exactly only those that can hold the largest estimate: a bound of |D_l^-1 R_l|_max in the
modes of the mean system (:mod:`periodyn.harmonic.mean_modal`, O(n^2) per l) below the largest
estimate solved so far means the harmonic cannot change the indicator, and it is not solved
(the value is the same as with every harmonic solved). From MODAL_MIN coordinates the
harmonics it solves, it solves in the same modes by a Jacobi iteration (O(n^2) per step, 4-5
steps) instead of the O(n^3) complex LU, which it takes only where the bound does not hold or
the steps do not converge.
"""

from __future__ import annotations

import numpy as np

from ..numerics.spectra import half_synthesis, min_samples, sample_angles, synthesize
from .mean_modal import BLOCK, MeanModalSystem  # BLOCK: speeds per matrix product of the samples

__all__ = ["BALANCE_TRUNCATION_TOL", "BalanceTruncationWarning", "balance_truncation", "balance_truncation_message",
           "SweepTruncation", "above_noise", "coefficient_terms", "coefficient_tops", "noise_floors"]

#: indicator above which a periodic solution is called unresolved (amplitudes then differ
#: from the integrated orbit by up to about this fraction or more: benchmarks/property_run.py)
BALANCE_TRUNCATION_TOL = 1e-2
_NEGLIGIBLE = 1e-13  # coefficient harmonics below this fraction of the largest are left out


class BalanceTruncationWarning(UserWarning):
    """A harmonic-balance solution leaves out harmonics of the size of those it keeps."""


def _reach(S: int, *spectra: np.ndarray) -> np.ndarray:
    """Highest harmonic |k| per speed (S,) with an entry above _NEGLIGIBLE of that speed's
    largest, over spectra (S, 2K+1, ...) (index k+K)."""
    return _top(sum(np.abs(x).reshape(S, x.shape[1], -1).max(axis=2) for x in spectra))  # of (S, 2K+1)


def balance_truncation(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, force: np.ndarray,
                       q: np.ndarray, omega) -> np.ndarray:
    """Indicator (S,) of the HB solutions q (S, 2m+1, n) at speeds omega (S,) rad/s, with
    coefficient spectra mass (2K+1, n, n) or (S, 2K+1, n, n), damping and stiffness
    (S, 2K+1, n, n), force (S, 2K+1, n) (index k+K). NaN where q is not finite. Each speed's
    value depends on its own spectra only (the coefficient band and the forced harmonics
    are per speed), so a sweep's chunking does not change it by a bit."""
    w = np.atleast_1d(np.asarray(omega, float))
    S, H, n = q.shape
    m = (H - 1) // 2
    M = np.broadcast_to(mass, damping.shape)
    K = (damping.shape[1] - 1) // 2
    Kf = (force.shape[1] - 1) // 2
    band = _reach(S, M, damping, stiffness)              # (S,) coefficient band
    top = np.maximum(m + band, _reach(S, force))         # (S,) highest unbalanced harmonic
    scale = np.abs(q).reshape(S, -1).max(axis=1)
    out = np.zeros(S)
    for l in range(m + 1, int(top.max(initial=m)) + 1):
        R = force[:, Kf + l].copy() if l <= Kf else np.zeros((S, n), complex)
        for j in range(max(-m, l - int(band.max())), m + 1):
            coupled = (l - j <= band)[:, None, None]              # |l - j| within this speed's band
            jw = (j * w)[:, None, None]
            A = np.where(coupled, -jw ** 2 * M[:, K + l - j] + 1j * jw * damping[:, K + l - j]
                         + stiffness[:, K + l - j], 0.0)
            R -= np.einsum("sab,sb->sa", A, q[:, m + j])
        lw = (l * w)[:, None, None]
        D = -lw ** 2 * M[:, K] + 1j * lw * damping[:, K] + stiffness[:, K]
        try:
            est = np.abs(np.linalg.solve(D, R[..., None])[..., 0])
        except np.linalg.LinAlgError:  # one speed's mean system resonates at harmonic l: solve one by one
            est = np.array([_estimate(D[s], R[s]) for s in range(S)])
        out = np.where(l <= top, np.maximum(out, est.max(axis=1)), out)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(scale > 0, out / scale, 0.0)
    return np.where(np.isfinite(q).reshape(S, -1).all(axis=1), ratio, np.nan)


def _magnitudes(X: np.ndarray) -> np.ndarray:
    """Largest entry modulus per harmonic (2K+1,) of a spectrum X (2K+1, ...)."""
    return np.abs(X).reshape(X.shape[0], -1).max(axis=1)


def _top(mags: np.ndarray) -> np.ndarray:
    """Highest harmonic |k| per row (S,) of harmonic magnitudes (S, 2K+1) above _NEGLIGIBLE
    of the row's largest."""
    K = (mags.shape[1] - 1) // 2
    big = mags > _NEGLIGIBLE * mags.max(axis=1, keepdims=True)
    return np.where(big, np.abs(np.arange(2 * K + 1) - K), 0).max(axis=1)


#: a harmonic is solved where SLACK times its bound reaches the largest estimate so far: the
#: bound holds exactly (measured 1.0-1.3x the estimate), SLACK - 1 is room for the rounding of
#: the bound and of the solve (1e-14 to 1e-13 of them)
SLACK = 1.0 + 1e-6
#: coordinates from which the harmonics are solved by the modal iteration: its 4-5 steps of
#: 4 Q n^2 flops per harmonic cost less than the complex LU's 8/3 n^3 from n ~ 45 (Q = 6 terms);
#: at 16 coordinates (chunks of 6 speeds) the iteration took 1.4x the LU, at 256 a quarter
MODAL_MIN = 64
#: a coefficient harmonic below FLOOR times the noise floor of the terms (the largest entry
#: modulus of their top quarter of harmonics, where that is resolved) is noise: at 128 rod
#: elements the floor is 3e-13 of the largest entry, from the kinematic Newton tolerance;
#: measured noise harmonics reach 1.2x the floor, the mass's smallest kept harmonics 6x
FLOOR = 3.0
#: a term's top quarter of harmonics is its noise floor where below this of its largest
RESOLVED = 1e-8


class SweepTruncation:
    """The indicator of :func:`balance_truncation` at many speeds of one constant-speed model.

    spectra: the model's power spectra (mass (2K+1, n, n), damping (2K+1, n, n, Pc),
    stiffness (2K+1, n, n, Pk), force (2K+1, n, Pf)); m: harmonics. Per speed, the band
    (:meth:`content`: cut at the terms' noise floors) and the force's reach come from the
    bound sum_p w^p max|X_p,k| of each harmonic's largest entry, and the harmonics
    l = m+1 .. max(m + band, reach) are estimated, solved where their modal bound can reach
    the largest (:meth:`bounds`). The products take the terms with harmonics above noise
    (:func:`above_noise`) with every coefficient harmonic up to the highest any term has
    above _NEGLIGIBLE of its own largest (B, a per-model constant) on P = 2(m + B) + 1
    angles. Each speed's value depends on its own data only, and every product runs per speed or on blocks of BLOCK speeds,
    never as one matrix product over a varying number of speeds (whose rounding depends on
    it): a speed's value is the same to the bit in any chunk."""

    def __init__(self, spectra: tuple[np.ndarray, ...], m: int):
        Ms, Cs, Ks, fs = spectra
        terms, self.mags, self.floors, self.exponents = coefficient_terms(Ms, Cs, Ks)
        K, Kf = (Ms.shape[0] - 1) // 2, (fs.shape[0] - 1) // 2
        self.m, self.n, self.powers = m, Ms.shape[1], (Cs.shape[-1], Ks.shape[-1])
        self.force_mags = np.stack([_magnitudes(fs[..., p]) for p in range(fs.shape[-1])])  # (Pf, 2Kf+1)
        self.B = B = int(_top(self.mags).max())
        self.l = np.arange(m + 1, max(m + B, Kf) + 1)  # (L,) the unbalanced harmonics any speed can have
        self.theta = theta = sample_angles(min_samples(m, B))
        self.terms, self._samples = [X[K - B: K + B + 1] for X in terms], {}  # harmonics |k| <= B; their samples
        # samples Re(sum_a z_a e^(i a theta)) from the real part's harmonics zs_a = (z_a + conj z_-a) / 2, a >= 0
        self.synthesis = half_synthesis(m, theta)  # (P, 2(m+1))
        self.analysis = np.exp(-1j * np.outer(self.l, theta)) / theta.size  # (L, P)
        self.mean = [X[K] for X in terms]  # mean blocks (n, n) of the terms
        stack = np.stack(self.mean)  # (Q, n, n)
        self.mean_stack = stack.real if not stack.imag.any() else stack  # real where they are: half the work
        self.modal = MeanModalSystem.of(self.mean, Cs.shape[-1])
        inside = self.l <= Kf
        self.force = np.zeros((self.l.size, self.n, fs.shape[-1]), complex)
        self.force[inside] = fs[Kf + self.l[inside]]

    def samples(self, t: int) -> np.ndarray:
        """Term t at the P angles (P, n, n) (built on first use: the products take only the
        terms with harmonics above noise)."""
        if t not in self._samples:
            self._samples[t] = synthesize(self.terms[t], self.theta)
        return self._samples[t]

    def content(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Coefficient band (S,) and the terms the products take (S, Q) at speeds w (S,)
        (elementwise, per speed). The band: the highest harmonic of the bound sum_p w^p
        max|X_p,k| above the larger of _NEGLIGIBLE of its largest and FLOOR times the terms'
        noise floors sum_p w^p floor_p. The terms: :func:`above_noise`."""
        total = (w[:, None, None] ** self.exponents[:, None] * self.mags[None]).sum(axis=1)  # (S, 2K+1)
        cut = np.maximum(_NEGLIGIBLE * total.max(axis=1), FLOOR * (w[:, None] ** self.exponents * self.floors).sum(axis=1))
        k = np.abs(np.arange(total.shape[1]) - (total.shape[1] - 1) // 2)
        band = np.minimum(np.where(total > cut[:, None], k, 0).max(axis=1), self.B)
        return band, above_noise(self.mags, self.floors, self.exponents, w)

    def tops(self, w: np.ndarray, band: np.ndarray | None = None) -> np.ndarray:
        """Highest unbalanced harmonic per speed (S,) at speeds w (S,): the band (S,) of
        :meth:`content` (computed when not given) past m, or the force's reach if higher."""
        reach = _top((w[:, None, None] ** np.arange(len(self.force_mags))[:, None] * self.force_mags[None]).sum(axis=1))
        return np.maximum(self.m + (self.content(w)[0] if band is None else band), reach)

    def unbalanced(self, q: np.ndarray, w: np.ndarray, used: np.ndarray | None = None) -> np.ndarray:
        """Unbalanced harmonics R (S, L, n) (index l - m - 1) of the HB solutions q (S, 2m+1, n)
        at speeds w (S,), from the terms used (S, Q) at each speed (:meth:`content`, computed
        when not given): per term, the samples of its harmonics of q'', w^p q' or w^p q per
        speed, times the term's samples on blocks of BLOCK speeds, summed per speed in term order."""
        S, m, (Pc, Pk) = w.size, self.m, self.powers
        used = self.content(w)[1] if used is None else used  # (S, Q)
        jw = (np.arange(-m, m + 1)[None, :] * w[:, None])[..., None]  # (S, 2m+1, 1)
        wp = w[:, None, None]
        factors = [-jw ** 2] + [1j * jw * wp ** p for p in range(Pc)] + [wp ** p + 0 * jw for p in range(Pk)]
        blocks = -(-S // BLOCK)
        r = np.zeros((blocks * BLOCK, self.synthesis.shape[0], self.n))  # (S padded, P, n)
        for t in np.flatnonzero(used.any(axis=0)):
            z = np.zeros((blocks * BLOCK, self.synthesis.shape[0], self.n))
            fq = factors[t] * q
            half = 0.5 * (fq[:, m:] + np.conj(fq[:, m::-1]))  # (S, m+1, n)
            z[:S] = np.matmul(self.synthesis[None], np.concatenate([half.real, half.imag], axis=1))  # samples, per speed
            zb = np.ascontiguousarray(z.reshape(blocks, BLOCK, *z.shape[1:]).transpose(0, 2, 3, 1))  # (blocks, P, n, BLOCK)
            rt = np.matmul(self.samples(t)[None], zb).transpose(0, 3, 1, 2).reshape(r.shape)
            r[:S] += np.where(used[:, t, None, None], rt[:S], 0.0)
        return np.einsum("lnf,sf->sln", self.force, w[:, None] ** np.arange(self.force.shape[-1])) \
            - np.matmul(self.analysis[None], r[:S])  # (S, L, n), per speed

    def __call__(self, q: np.ndarray, omega: np.ndarray) -> np.ndarray:
        """Indicators (S,) of the HB solutions q (S, 2m+1, n) at speeds omega (S,) rad/s (NaN
        where q is not finite)."""
        w = np.asarray(omega, float)
        S = w.size
        band, used = self.content(w)
        top = self.tops(w, band)
        R = self.unbalanced(q, w, used)
        bound = self.bounds(R, w, top)
        order = np.argsort(-bound, axis=1, kind="stable")  # per speed, the largest bound first
        out = np.zeros(S)
        for rank in range(self.l.size):
            i = order[:, rank]
            at = np.flatnonzero(SLACK * bound[np.arange(S), i] > out)
            if not at.size:
                break
            i = i[at]
            est = np.full((at.size, self.n), np.nan)
            modal = np.isfinite(bound[at, i]) & (self.n >= MODAL_MIN)  # it converges where the bound holds
            if modal.any():
                est[modal] = self.modal_estimates(R[at[modal], i[modal]], self.l[i[modal]] * w[at[modal]], w[at[modal]])
            dense = np.flatnonzero(np.isnan(est).any(axis=1))
            if dense.size:
                est[dense] = self.dense_estimates(R[at[dense], i[dense]], self.l[i[dense]] * w[at[dense]], w[at[dense]])
            out[at] = np.maximum(out[at], est.max(axis=1))
        scale = np.abs(q).reshape(S, -1).max(axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.where(scale > 0, out / scale, 0.0)
        return np.where(np.isfinite(q).reshape(S, -1).all(axis=1), ratio, np.nan)

    def _coefficients(self, lw: np.ndarray, w: np.ndarray) -> np.ndarray:
        """Weights (V, Q) of the terms' mean blocks in D_l = sum_t coef_t Xbar_t at lw = l w (V,)
        and speeds w (V,): -(l w)^2 for M, i l w w^p for C_p, w^p for K_p."""
        Pc, Pk = self.powers
        wp = w[:, None] ** np.arange(max(Pc, Pk))  # (V, P)
        return np.concatenate([-lw[:, None] ** 2, 1j * lw[:, None] * wp[:, :Pc], wp[:, :Pk] + 0j], axis=1)

    def modal_estimates(self, R: np.ndarray, lw: np.ndarray, w: np.ndarray) -> np.ndarray:
        """|D_l^-1 R_l| (V, n) of the unbalanced harmonics R (V, n) at lw = l w (V,) and speeds
        w (V,) by the Jacobi iteration in the mean modes (NaN where it did not converge; each
        vector's value its own to the bit)."""
        return self.modal.solve_moduli(self._coefficients(lw, w), R)

    def dense_estimates(self, R: np.ndarray, lw: np.ndarray, w: np.ndarray) -> np.ndarray:
        """|D_l^-1 R_l| (V, n) by dense solves of D_l (inf where the mean system resonates at
        the harmonic), D_l formed elementwise per vector (a vector's rounding does not depend on V)."""
        Pc = self.powers[0]
        M, C, K = self.mean_stack[0], self.mean_stack[1: 1 + Pc], self.mean_stack[1 + Pc:]
        wa, lw = w[:, None, None], lw[:, None, None]
        D = (-lw ** 2 * M + sum(wa ** p * X for p, X in enumerate(K))
             + 1j * (lw * sum(wa ** p * X for p, X in enumerate(C))))
        try:
            return np.abs(np.linalg.solve(D, R[..., None])[..., 0])
        except np.linalg.LinAlgError:  # one speed's mean system resonates at its harmonic
            return np.array([_estimate(Dj, Rj) for Dj, Rj in zip(D, R)])

    def bounds(self, R: np.ndarray, w: np.ndarray, top: np.ndarray) -> np.ndarray:
        """Upper bounds (S, L) of |D_l^-1 R_l|_max for the unbalanced harmonics R (S, L, n) at
        speeds w (S,) (module docstring): inf where the modal bound does not hold (rho >= 1,
        no modal basis, not finite), -inf for the harmonics l > top (S,) a speed leaves out."""
        S, L = R.shape[:2]
        out = np.full((S, L), -np.inf)
        s, i = np.nonzero(self.l[None, :] <= top[:, None])  # the (speed, harmonic) pairs, (V,) each
        if self.modal is None or not s.size:
            out[s, i] = np.inf
            return out
        out[s, i] = self.modal.bounds(self._coefficients(self.l[i] * w[s], w[s]), R[s, i])
        return out


def coefficient_terms(Ms: np.ndarray, Cs: np.ndarray, Ks: np.ndarray) -> tuple[list, np.ndarray, np.ndarray, np.ndarray]:
    """The Q = 1 + Pc + Pk coefficient terms [M, C_p.., K_p..] (each (2K+1, n, n)) of power
    spectra Ms (2K+1, n, n), Cs (2K+1, n, n, Pc), Ks (2K+1, n, n, Pk), their harmonic
    magnitudes (Q, 2K+1) (largest entry modulus per harmonic), noise floors (Q,)
    (:func:`noise_floors`) and omega-powers (Q,)."""
    terms = [Ms] + [Cs[..., p] for p in range(Cs.shape[-1])] + [Ks[..., p] for p in range(Ks.shape[-1])]
    mags = np.stack([_magnitudes(X) for X in terms])
    return terms, mags, noise_floors(mags), np.array([0] + list(range(Cs.shape[-1])) + list(range(Ks.shape[-1])))


def above_noise(mags: np.ndarray, floors: np.ndarray, exponents: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Terms (S, Q) with a non-mean harmonic above noise at speeds w (S,), of harmonic
    magnitudes mags (Q, 2K+1) with noise floors (Q,) (:func:`noise_floors`) and omega-powers
    exponents (Q,): a term with a floor where a harmonic rises FLOOR times above it (at
    every speed), one without (not decayed, or exactly zero) where one is above _NEGLIGIBLE
    of the largest of the bound sum_p w^p max|X_p,k|."""
    terms = w[:, None, None] ** exponents[:, None] * mags[None]  # (S, Q, 2K+1)
    k = np.abs(np.arange(mags.shape[1]) - (mags.shape[1] - 1) // 2)
    above = (mags[:, k > 0] > FLOOR * floors[:, None]).any(axis=1) & (floors > 0)  # (Q,)
    largest = _NEGLIGIBLE * terms.sum(axis=1).max(axis=1)
    return above | (floors == 0) & (terms[:, :, k > 0] > largest[:, None, None]).any(axis=2)


def coefficient_tops(mags: np.ndarray, floors: np.ndarray) -> np.ndarray:
    """Highest harmonic |k| (Q,) of each term's harmonic magnitudes (Q, 2K+1) above FLOOR
    times its noise floor (Q,) (:func:`noise_floors`; the harmonics above it are noise), or
    above _NEGLIGIBLE of its largest where it has no floor."""
    K = (mags.shape[1] - 1) // 2
    k = np.abs(np.arange(2 * K + 1) - K)
    above = np.where(floors[:, None] > 0, mags > FLOOR * floors[:, None],
                     mags > _NEGLIGIBLE * mags.max(axis=1, keepdims=True))
    return np.where(above, k, 0).max(axis=1)


def noise_floors(mags: np.ndarray) -> np.ndarray:
    """Noise floor (Q,) of each term's harmonic magnitudes (Q, 2K+1): the largest of its top
    quarter of harmonics where that is below RESOLVED of its largest entry, else 0 (a term
    whose spectrum has not decayed keeps every harmonic above _NEGLIGIBLE)."""
    K = (mags.shape[1] - 1) // 2
    tail = np.abs(np.arange(2 * K + 1) - K) >= K - K // 4
    floor = mags[:, tail].max(axis=1)
    return np.where(floor <= RESOLVED * mags.max(axis=1), floor, 0.0)


def _estimate(D: np.ndarray, R: np.ndarray) -> np.ndarray:
    """|D^-1 R| (n,) of one speed; inf where the mean system resonates at this harmonic."""
    try:
        return np.abs(np.linalg.solve(D, R))
    except np.linalg.LinAlgError:
        return np.full(R.shape, np.inf)


def balance_truncation_message(indicator: float, m: int, omega: float) -> str:
    """Why a periodic solution is unresolved, and the fix."""
    return (f"harmonic balance with harmonics = {m} leaves out harmonics at omega = {omega:.6g} rad/s of "
            f"{indicator:.2g} of the largest kept one (tolerance {BALANCE_TRUNCATION_TOL:g}): its amplitudes may be "
            "wrong; increase harmonics")
