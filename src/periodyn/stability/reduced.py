"""Stability method "reduced": the certified Magnus ladder on a mean-system modal
reduction (:mod:`periodyn.model.reduce`) with a Schur-complement correction for the
modes left out, for large element models.

In the modal coordinates of all n mean-system modes, split into the k kept (l) and the
truncated (h), Hill's operator is Q_ab(lambda) = s_b^2 M_(a-b) + s_b C_(a-b) + K_(a-b),
s_b = lambda + i b omega (harmonics a, b = -m..m; M, C, K the coefficient spectra at the
speed). For the dominant exponent lambda of the reduced model (its ladder, to
LADDER_TOL) with the right and left null vectors x, y of the reduced Hill operator Q_ll
(shifted by i j omega until x is centred in the harmonics), the truncated modes move
lambda by the first Schur-complement term

    d_lambda = sum_a s_h[a] D_a^-1 r_h[a] / (y^H Q'_ll(lambda) x),   r_h = Q_hl x,  s_h = y^H Q_lh,
    D_a = s_a^2 Mbar_hh + s_a Cbar_hh + Kbar_hh        (the mean truncated block),

and the corrected growth per period is Re(lambda + d_lambda) T with the error bound
ladder error + 2 |d_lambda| T. A speed is certified when the bound is at most
STABILITY_TOL max(1, |G|) and below the distance of G from the verdict's threshold;
otherwise (also near a double exponent, y^H Q' x -> 0, where no centred null vector
exists, or where a truncated mode's diagonal estimate comes near the top) the mode count
doubles, and a speed not certified with fewer than n modes goes to "auto" on the full
model. Exponents of the truncated modes are their mean diagonal estimates (roots of
s^2 + c_ii s + k_ii), so a sweep records 2n exponents.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from ..model.reduce import guarded_modes, mean_modes
from ..system import OmegaSplitModel, RheoLinear
from ..kernels.solvers import magnus_ladder as kernel
from .floquet import STABILITY_TOL
from .magnus import MagnusLadder

__all__ = ["ReducedStability", "system_model", "reduced_choices", "LADDER_TOL", "START_MODES"]

LADDER_TOL = 1e-9  # error goal of log max|mu| for the reduced ladder (its floor: ERROR_FLOOR)
# modes of the first try, before the parametric-reach guard: with 4 the bound (3e-6 to 4e-5
# on the 4-64-element slider-cranks over 150-300 rad/s) was above the tolerance at every speed
START_MODES = 8
WINDOW = 1.0  # exponents with growth per period within this of the top are corrected
EDGE_MAX = 0.05  # largest energy fraction of a centred Hill null vector in the harmonics |a| = m
DOUBLE_TOL = 1e-6  # |y^H Q' x| / max|Q'| below this: a near double exponent
JACOBI_STEPS = 20  # Jacobi sweeps on the mean truncated blocks D_a before their dense solve
JACOBI_RTOL = 1e-12  # relative residual of D_a z_a = r_a at which the sweeps stop


class _Ladder(MagnusLadder):
    """The certified Magnus ladder with the error goal ``tol`` instead of STABILITY_TOL."""

    def __init__(self, mass, damping, stiffness, tol: float):
        self.tol = tol
        super().__init__(mass, damping, stiffness)

    def config(self) -> np.ndarray:
        c = super().config()
        c[kernel.CFG_TOL] = self.tol
        return c


def _pairs(K: int, m: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Index arrays (a, b, a - b + K) of the harmonic pairs a, b = -m..m with |a - b| <= K."""
    a, b = np.meshgrid(np.arange(2 * m + 1), np.arange(2 * m + 1), indexing="ij")
    keep = np.abs(a - b) <= K
    return a[keep], b[keep], (a - b)[keep] + K


def _apply(spectra, weights: np.ndarray, x: np.ndarray, m: int) -> np.ndarray:
    """r_a = sum_b sum_q weights[q, b] X^q_(a-b) x_b for spectra X^q (2K+1, r, c), weights
    (Q, 2m+1), x (2m+1, c): (2m+1, r), without forming the (2m+1)^2 blocks."""
    a, b, d = _pairs((spectra[0].shape[0] - 1) // 2, m)
    out = np.zeros((2 * m + 1, spectra[0].shape[1]), dtype=complex)
    for X, wq in zip(spectra, weights):
        P = X @ (wq[:, None] * x).T  # (2K+1, r, 2m+1)
        np.add.at(out, a, P[d, :, b])
    return out


def _offsets(X: np.ndarray, m: int) -> np.ndarray:
    """Coefficients X_(a-b) for a, b = -m..m from a spectrum (2K+1, ...), (2m+1, 2m+1, ...)."""
    K = (X.shape[0] - 1) // 2
    d = np.arange(-m, m + 1)[:, None] - np.arange(-m, m + 1)[None, :]
    out = np.zeros(d.shape + X.shape[1:], dtype=complex)
    inside = np.abs(d) <= K
    out[inside] = X[d[inside] + K]
    return out


def _truncated_solve(Mh: np.ndarray, Ch: np.ndarray, Kh: np.ndarray, s: np.ndarray, r: np.ndarray) -> np.ndarray:
    """z (2m+1, h) with D_a z_a = r_a, D_a = s_a^2 Mh + s_a Ch + Kh (mean truncated block
    (h, h) each, s (2m+1,), r (2m+1, h)): Jacobi sweeps on the diagonal (in mean-modal
    coordinates the blocks are diagonal up to the speed-dependent and non-proportional
    terms, small against the stiff truncated modes), O(m h^2) each, to JACOBI_RTOL; where
    they do not converge within JACOBI_STEPS, the dense solves (O(m h^3))."""
    d = (s * s)[:, None] * np.diag(Mh) + s[:, None] * np.diag(Ch) + np.diag(Kh)
    z = r / d
    scale = np.linalg.norm(r)
    for _ in range(JACOBI_STEPS):
        res = r - ((s * s)[:, None] * (z @ Mh.T) + s[:, None] * (z @ Ch.T) + z @ Kh.T)
        if np.linalg.norm(res) <= JACOBI_RTOL * scale:
            return z
        z = z + res / d
    D = s[:, None, None] ** 2 * Mh[None] + s[:, None, None] * Ch[None] + Kh[None]
    return np.linalg.solve(D, r[..., None])[..., 0]


def _null_vectors(Q: np.ndarray, iterations: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """Right and left null vectors x, y (unit) of a nearly singular square Q by inverse
    iteration on one LU (Q x ~ 0, y^H Q ~ 0)."""
    lu = sla.lu_factor(Q, check_finite=False)
    x = np.linspace(1.0, 2.0, Q.shape[0]) + 0j
    y = x.copy()
    for _ in range(iterations):
        x = sla.lu_solve(lu, x, check_finite=False)
        y = sla.lu_solve(lu, y, trans=2, check_finite=False)
        x, y = x / np.linalg.norm(x), y / np.linalg.norm(y)
    return x, y


class ReducedStability:
    """Per-model data of the method "reduced": the full model's spectra in the modal
    coordinates of its mean system at ``reference_speed`` rad/s, and the reduced ladders
    (built per mode count on first use)."""

    def __init__(self, model: OmegaSplitModel, reference_speed: float = 0.0):
        self.model, self.n = model, model.n
        self.modes = mean_modes(model, reference_speed)
        Phi = self.modes.shapes
        Ms, Cs, Ks = model._power_spectra[:3]
        self.M = np.einsum("ni,knm,mj->kij", Phi, Ms, Phi, optimize=True)
        self.C = np.einsum("ni,knmp,mj->kijp", Phi, Cs, Phi, optimize=True)
        self.K = np.einsum("ni,knmp,mj->kijp", Phi, Ks, Phi, optimize=True)
        self._ladders: dict[int, _Ladder] = {}

    def ladder(self, k: int) -> _Ladder:
        """The ladder of the k-mode model (spectra of the projected samples)."""
        if k not in self._ladders:
            self._ladders[k] = _Ladder(self.M[:, :k, :k], self.C[:, :k, :k], self.K[:, :k, :k], LADDER_TOL)
        return self._ladders[k]

    def _at(self, w: float, rows: slice, cols: slice, mean: bool = False) -> tuple[np.ndarray, ...]:
        """Modal spectra M, C, K (2K+1, r, c) of the block (rows, cols) at speed w (only the
        mean coefficients (r, c) with ``mean``)."""
        k = slice((self.M.shape[0] - 1) // 2, (self.M.shape[0] + 1) // 2) if mean else slice(None)
        M, C, K = (X[k, rows, cols] for X in (self.M, self.C, self.K))
        out = (M, C @ w ** np.arange(C.shape[-1]), K @ w ** np.arange(K.shape[-1]))
        return tuple(X[0] for X in out) if mean else out

    def truncated_exponents(self, w: float, k: int) -> np.ndarray:
        """Diagonal mean estimates (2(n-k),) of the exponents of the truncated modes."""
        h = slice(k, self.n)
        M, C, K = self._at(w, h, h, mean=True)
        c, kk, mm = np.diag(C).real, np.diag(K).real, np.diag(M).real
        disc = np.sqrt((c * c - 4 * mm * kk).astype(complex))
        return np.concatenate([(-c + disc) / (2 * mm), (-c - disc) / (2 * mm)])

    def mean_exponents(self, w: float, k: int) -> np.ndarray:
        """Exponents (2k,) of the kept modes' mean system at speed w (the representatives'
        first guess: a Floquet exponent lies near one of them)."""
        l = slice(0, k)
        M, C, K = self._at(w, l, l, mean=True)
        A = np.block([[np.zeros((k, k)), np.eye(k)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
        return np.linalg.eigvals(A)

    def correction(self, lam: complex, w: float, m: int, k: int) -> tuple[complex, complex, str]:
        """(centred exponent, d_lambda, "") of the reduced exponent lam at speed w with m
        harmonics and k kept modes, or (lam, nan, why) where it is not determined."""
        l, h = slice(0, k), slice(k, self.n)
        M, C, K = (_offsets(X, m) for X in self._at(w, l, l))  # (2m+1, 2m+1, k, k)
        a = np.arange(-m, m + 1)
        N = (2 * m + 1) * k
        nu = self.mean_exponents(w, k)
        j = np.rint((nu.imag - lam.imag) / w)
        lam = lam + 1j * w * j[np.argmin(np.abs(lam + 1j * w * j - nu))]
        x = y = None
        for _ in range(3):
            s = lam + 1j * a * w  # s_b per column harmonic b
            Qll = s[None, :, None, None] ** 2 * M + s[None, :, None, None] * C + K
            x, y = _null_vectors(Qll.transpose(0, 2, 1, 3).reshape(N, N))
            x, y = x.reshape(2 * m + 1, k), y.reshape(2 * m + 1, k)
            energy = (np.abs(x) ** 2).sum(axis=1)
            shift = int(np.rint(energy @ a / energy.sum()))
            if shift == 0:
                break
            lam = lam + 1j * shift * w
        else:
            return lam, np.nan, "no centred reduced-Hill null vector"
        energy = (np.abs(x) ** 2).sum(axis=1)
        if (energy[0] + energy[-1]) / energy.sum() > EDGE_MAX:
            return lam, np.nan, "the reduced-Hill null vector reaches the outermost harmonics"
        dQ = 2 * s[None, :, None, None] * M + C
        denom = np.einsum("ai,abij,bj->", y.conj(), dQ, x)
        if abs(denom) < DOUBLE_TOL * np.abs(dQ).max():
            return lam, np.nan, "near a double exponent (y^H Q' x -> 0)"
        weights = np.stack([s * s, s, np.ones_like(s)])
        r = _apply(self._at(w, h, l), weights, x, m)
        # s_h[b] = sum_a y_a^H Q_lh[a, b]: the transposed convolution, harmonics reversed
        ones = np.ones((1, 2 * m + 1))
        sh = sum(wq[:, None] * _apply([np.conj(X[::-1].transpose(0, 2, 1))], ones, y, m).conj()
                 for X, wq in zip(self._at(w, l, h), weights))
        z = _truncated_solve(*self._at(w, h, h, mean=True), s, r)
        return lam, complex(np.einsum("ai,ai->", sh, z) / denom), ""

    def certify(self, w: float, m: int, k: int, exps: np.ndarray, error: float):
        """Corrected exponents (2k,), growth G, bound, largest |d_lambda| T and why not
        certified ("" if certified) at one speed from the reduced ladder's result."""
        T = 2 * np.pi / w
        if not np.isfinite(error) or not np.isfinite(exps).all():
            return exps, np.nan, np.inf, np.nan, "the reduced ladder did not resolve the multipliers"
        out = exps.copy()
        top = exps.real.max() * T
        largest, done = 0.0, []
        for i in np.nonzero(exps.real * T >= top - WINDOW)[0]:
            pair = [j for j in done if abs(exps[i] - np.conj(exps[j])) <= 1e-12 * abs(exps[j]) and exps[j].imag]
            if pair:  # the conjugate of a corrected exponent: its correction is the conjugate
                out[i] = np.conj(out[pair[0]])
                continue
            lam, d, why = self.correction(exps[i], w, m, k)
            if why:
                return exps, np.nan, np.inf, np.nan, why
            out[i] = lam + d
            largest = max(largest, abs(d) * T)
            done.append(i)
        G = out.real.max() * T
        bound = error + 2 * largest
        if self.truncated_exponents(w, k).real.max() * T >= G - bound:
            return out, G, bound, largest, "a truncated mode's estimate reaches the top exponent"
        if bound > STABILITY_TOL * max(1.0, abs(G)) or abs(G - STABILITY_TOL) <= bound:
            return out, G, bound, largest, f"bound {bound:.2g} above the tolerance or the verdict margin"
        return out, G, bound, largest, ""

    def solve(self, w: np.ndarray, m: int):
        """Exponents (S, 2n), certified (S,), reasons (S,) and the per-speed records
        {``reduced_modes``: k (0 where not certified), ``reduced_correction``: largest
        |d_lambda| 1/s, ``stability_error_bound``: bound of max Re(lambda) T (NaN where not
        certified)} (S,) at speeds w (S,) rad/s with m harmonics (each speed's result
        independent of the others)."""
        S = w.size
        exps = np.full((S, 2 * self.n), np.nan + 0j)
        done = np.zeros(S, bool)
        reasons = np.full(S, "", dtype=object)
        records = {"reduced_modes": np.zeros(S, np.int32), "reduced_correction": np.full(S, np.nan),
                   "stability_error_bound": np.full(S, np.nan)}
        k = np.array([guarded_modes(self.modes, min(START_MODES, self.n), m, wi) for wi in w])
        small = k >= self.n
        reasons[small] = f"{self.n} coordinates: no modes to leave out"
        todo = np.nonzero(~small)[0]
        while todo.size:
            for kk in np.unique(k[todo]):
                group = todo[k[todo] == kk]
                est = self.ladder(int(kk)).solve(w[group], np.inf)
                for j, s in enumerate(group):
                    out, G, bound, dl, why = self.certify(w[s], m, int(kk), est.exponents[j], est.error[j])
                    if why:
                        reasons[s] = f"{kk} modes: {why}"
                        continue
                    exps[s, : 2 * kk] = out
                    exps[s, 2 * kk:] = self.truncated_exponents(w[s], int(kk))
                    done[s] = True
                    records["reduced_modes"][s] = kk
                    records["reduced_correction"][s] = dl * w[s] / (2 * np.pi)
                    records["stability_error_bound"][s] = bound
                    reasons[s] = (f"reduced: {kk} of {self.n} modes, ladder error {est.error[j]:.1g}, "
                                  f"correction {dl:.2g} per period, bound {bound:.2g}")
            todo = np.array([s for s in todo if not done[s] and 2 * k[s] < self.n], dtype=int)
            k[todo] *= 2
        order = np.lexsort((exps.imag, exps.real), axis=-1)
        return np.take_along_axis(exps, order, -1), done, reasons, records


def system_model(system: RheoLinear) -> OmegaSplitModel:
    """One rheo-linear system as a model without omega-powers (its mean modes are the
    system's own)."""
    return OmegaSplitModel.from_samples(system.mass, [system.damping], [system.stiffness], [system.force])


def reduced_choices(stage, w: np.ndarray):
    """"reduced" per speed in a sweep: certified speeds solved, the others named "auto";
    k, the correction and the bound recorded per speed (the fill values elsewhere)."""
    exps, done, reasons, records = stage.prepared("reduced").solve(w, stage.m)
    names = np.where(done, "reduced", "auto").astype(object)
    return names, reasons, exps, done, records
