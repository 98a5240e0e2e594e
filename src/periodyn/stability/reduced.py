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

(r_h and s_h by products on band + 2m + 1 angles, band the highest coefficient harmonic
above the noise floors of the terms taken, measured on the coupling blocks, linear in n - k;
D_a^-1 by Jacobi sweeps on its diagonal, O(m (n-k)^2), :mod:`periodyn.stability.schur`); the
corrected growth per period is Re(lambda + d_lambda) T, its error bound ladder error +
2 |d_lambda| T. A speed is certified when the bound is at most STABILITY_TOL max(1, |G|) and
below the distance of G from the verdict's threshold; otherwise (also near a double exponent,
y^H Q' x -> 0, where no centred null vector exists, or where a truncated mode's diagonal
estimate comes near the top) the mode count doubles, and a speed not certified with fewer
than n modes goes to "auto" on the full model. Exponents of the truncated modes are their
mean diagonal estimates (roots of s^2 + c_ii s + k_ii): a sweep records 2n exponents.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from ..harmonic.truncation import above_noise, coefficient_tops, noise_floors
from ..model.reduce import guarded_modes, mean_modes, modal_spectrum
from ..numerics.spectra import sample_angles, synthesize
from ..system import OmegaSplitModel, RheoLinear
from ..kernels.solvers import magnus_ladder as kernel
from .floquet import STABILITY_TOL
from .magnus import MagnusLadder
from .schur import centred_null_vectors, harmonic_offsets, truncated_solve

__all__ = ["ReducedStability", "system_model", "reduced_choices", "reduced_first", "reduced_pays",
           "reduced_costs", "LADDER_TOL", "START_MODES", "AUTO_MIN_COORDINATES"]

# error goal of log max|mu| for the reduced ladder: 1e-8 leaves the bound's budget to the
# correction (2 |d_lambda| T up to 6.7e-7 on 16-128 elements against STABILITY_TOL = 1e-6) and
# the corrected exponent within 1e-8 (true ladder error at most 5.4e-10 on the 16-element
# slider-crank with 10 modes, 150-300 rad/s); at 1e-9 (the estimate's floor, ERROR_FLOOR) the
# ladder took 1.6 times as long
LADDER_TOL = 1e-8
# modes of the first try, before the parametric-reach guard: with 4 the bound (3e-6 to 4e-5
# on the 4-64-element slider-cranks over 150-300 rad/s) was above the tolerance at every speed;
# with 8 (bound 1e-7 to 2e-6) at 5 or 6 of 24 speeds, which then climbed the 16-mode ladder at
# about 3 times its cost; 10 (bound 6e-8 to 6.7e-7 on 16, 32, 64 and 128 elements) certifies
# them all at about 0.7 times the cost of 12 (bound 2e-8 to 3e-7)
START_MODES = 10
# "auto" considers the reduced method from this many coordinates (twice START_MODES: fewer
# leave too few modes out to pay for the correction; the Cardan shaft has 10)
AUTO_MIN_COORDINATES = 2 * START_MODES
# estimated seconds of one correction (the complex LU of the reduced Hill matrix, N = (2m+1) k,
# and the products; measured 4-6 ms at N = 300 on one core): CORRECTION_COST[0] N^3 + [1]
CORRECTION_COST = (1.0e-10, 2.0e-3)
LADDER_CLIMB = 3.0  # the reduced ladder's time over its first comparison (3.0-3.2 on the 16-128-element slider-cranks)
WINDOW = 1.0  # exponents with growth per period within this of the top are corrected
EDGE_MAX = 0.05  # largest energy fraction of a centred Hill null vector in the harmonics |a| = m
DOUBLE_TOL = 1e-6  # |y^H Q' x| over a bound of max|Q'| below this: a near double exponent
# the mean truncated mass block enters the Jacobi sweeps by its diagonal where its off-diagonal
# is at most this of its diagonal: in M-orthonormal modes it is the identity up to the rounding
# of the mean (1.5e-8 at 128 rod elements); the sweeps stop at a residual of JACOBI_RTOL = 1e-6
MASS_DIAGONAL = 1e-7


class _Ladder(MagnusLadder):
    """The certified Magnus ladder with the error goal ``tol`` instead of STABILITY_TOL."""

    def __init__(self, mass, damping, stiffness, tol: float):
        self.tol = tol
        super().__init__(mass, damping, stiffness)

    def config(self) -> np.ndarray:
        c = super().config()
        c[kernel.CFG_TOL] = self.tol
        return c


class ReducedStability:
    """Per-model data of the method "reduced" in the modal coordinates of the model's mean
    system at ``reference_speed`` rad/s, built on first use: the mean coefficients on all n
    modes, and per mode count k the kept block's spectra and ladder (the ladder's cost
    estimate needs only these) and the spectra of the coupling blocks (truncated rows and
    kept columns, and the transpose: the correction's products take no other entries)."""

    def __init__(self, model: OmegaSplitModel, reference_speed: float = 0.0):
        self.model, self.n = model, model.n
        self.modes = mean_modes(model, reference_speed)
        self.powers = (model.damping.shape[0], model.stiffness.shape[0])  # Pc, Pk
        self._ladders: dict[int, _Ladder] = {}
        self._kept: dict[int, tuple[np.ndarray, ...]] = {}
        self._blocks: dict[int, tuple[np.ndarray, ...]] = {}
        self._couplings: dict[tuple[int, int, int], tuple[np.ndarray, ...]] = {}
        self._hill: dict[tuple[int, int], np.ndarray] = {}
        self._hill_tops: dict[tuple[int, int], np.ndarray] = {}
        self._truncated: dict[int, tuple[np.ndarray, ...]] = {}

    @cached_property
    def _means(self) -> tuple[np.ndarray, ...]:
        """The mean coefficients on all n modes (real), M (n, n), C (Pc, n, n), K (Pk, n, n)."""
        out = []
        for X in self.model._power_spectra[:3]:
            K0 = (X.shape[0] - 1) // 2
            mean = modal_spectrum(X[K0: K0 + 1], self.modes.shapes)[0].real
            out.append(np.ascontiguousarray(np.moveaxis(mean, -1, 0)) if X.ndim == 4 else mean)
        return tuple(out)

    def blocks(self, k: int) -> tuple[np.ndarray, ...]:
        """Spectra of the coupling blocks of k kept modes per term [M, C_p.., K_p..], hl (2K+1,
        n-k, k, Q) and lh (2K+1, k, n-k, Q) (4 n^2 k products per harmonic, not the 4 n^3 of all
        modes), and the modal terms' harmonic magnitudes (Q, 2K+1) as the products see them
        (the mean over all n modes, the others over hl and lh: per-block noise floors against
        the scale of the whole term), noise floors, omega-powers and tops (built once per k)."""
        if k not in self._blocks:
            Phi = self.modes.shapes
            l, h = Phi[:, :k], Phi[:, k:]
            spectra = [X if X.ndim == 4 else X[..., None] for X in self.model._power_spectra[:3]]
            hl, lh = (np.concatenate([modal_spectrum(X, rows, cols) for X in spectra], axis=-1)
                      for rows, cols in ((h, l), (l, h)))
            mags = np.maximum(np.abs(hl).max(axis=(1, 2)), np.abs(lh).max(axis=(1, 2))).T  # (Q, 2K+1)
            M, C, K = self._means
            mags[:, (hl.shape[0] - 1) // 2] = [np.abs(X).max() for X in (M, *C, *K)]
            floors = noise_floors(mags)
            exponents = np.concatenate([[0], np.arange(len(C)), np.arange(len(K))])
            self._blocks[k] = (hl, lh, mags, floors, exponents, coefficient_tops(mags, floors))
        return self._blocks[k]

    def couplings(self, k: int, m: int, band: int) -> tuple[np.ndarray, ...]:
        """The coupling blocks of k kept modes with m harmonics and the coefficient harmonics
        |d| <= band at P = band + 2m + 1 angles (built once per (k, m, band)): synthesis E
        (P, 2m+1) of sum_a x_a e^(i a theta), per term (M, C_p, K_p) the real blocks hl
        (P, n-k, k), lh (P, k, n-k) and their means. No product of a harmonic |d| <= band with
        a harmonic |b| <= m aliases onto |a| <= m on these angles: the products are the
        harmonic convolutions, O(P (n-k) k) instead of O(m band (n-k) k)."""
        if (k, m, band) not in self._couplings:
            hl, lh = self.blocks(k)[:2]
            K0 = (hl.shape[0] - 1) // 2
            theta = sample_angles(band + 2 * m + 1)
            E = np.exp(1j * np.outer(theta, np.arange(-m, m + 1)))
            hl, lh = (X[K0 - band: K0 + band + 1] for X in (hl, lh))  # harmonics |d| <= band, (2 band + 1, ., ., Q)
            means = [np.moveaxis(X[band].real, -1, 0) for X in (hl, lh)]
            hl, lh = (np.moveaxis(synthesize(X, theta), -1, 0) for X in (hl, lh))
            self._couplings[k, m, band] = (E, np.ascontiguousarray(hl), np.ascontiguousarray(lh), *means)
        return self._couplings[k, m, band]

    def _coupled(self, w: float, k: int, m: int, s: np.ndarray, x: np.ndarray, y: np.ndarray, band=None):
        """r_h = Q_hl(lambda) x (2m+1, n-k) and s_h = y^H Q_lh(lambda) (2m+1, n-k) for
        Hill vectors x, y (2m+1, k) with s_b = lambda + i b w (2m+1,): per angle the terms
        with harmonics above noise (:func:`~periodyn.harmonic.truncation.above_noise` of the
        noise data of :meth:`blocks`) with their harmonics up to ``band`` (default: the
        highest of those terms above FLOOR times its noise floor, all of a term without a
        floor), the others by their mean blocks (their harmonics are the samples' rounding noise)."""
        mags, floors, exponents, tops = self.blocks(k)[2:]
        used = above_noise(mags, floors, exponents, np.array([w]))[0]
        band = int(tops[used].max(initial=0)) if band is None else band
        E, hl, lh, hl_mean, lh_mean = self.couplings(k, m, band)
        (Pc, Pk), P = self.powers, E.shape[0]
        powers = np.concatenate([[1.0], w ** np.arange(Pc), w ** np.arange(Pk)])
        weights = np.concatenate([[s * s], np.repeat(s[None], Pc, 0), np.ones((len(powers) - 1 - Pc, s.size))])
        weights = weights * powers[:, None]  # (1 + Pc + Pk, 2m+1): s_b^2 for M, s_b w^p for C_p, w^p for K_p
        r = np.zeros((2 * m + 1, self.n - k), complex)
        sh = np.zeros_like(r)
        ys = np.ascontiguousarray(np.conj(E) @ np.conj(y))  # sum_a conj(y_a) e^(-i a theta_j), (P, k)
        ysr = np.ascontiguousarray(ys.view(float).reshape(P, k, 2).transpose(0, 2, 1))  # (P, 2, k)
        for t in range(len(powers)):
            if used[t]:
                xs = np.ascontiguousarray(E @ (weights[t][:, None] * x))  # (P, k)
                R = np.matmul(hl[t], xs.view(float).reshape(P, k, 2))  # real and imaginary parts, (P, n-k, 2)
                r += np.conj(E.T) @ (R[..., 0] + 1j * R[..., 1]) / P
                T = np.matmul(ysr, lh[t])  # (P, 2, n-k)
                sh += weights[t][:, None] * (E.T @ (T[:, 0] + 1j * T[:, 1])) / P
            else:
                r += (weights[t][:, None] * x) @ hl_mean[t].T
                sh += weights[t][:, None] * (np.conj(y) @ lh_mean[t])
        return r, sh

    def hill_terms(self, k: int, m: int) -> np.ndarray:
        """The reduced Hill matrix's omega-power terms (1 + Pc + Pk, N, N), N = (2m+1) k, rows
        (a, i) and columns (b, j): M_(a-b), C_p,(a-b), K_p,(a-b) of the k kept modes (built
        once per (k, m)); Q_ll = s_b^2 M + s_b sum_p w^p C_p + sum_p w^p K_p."""
        if (k, m) not in self._hill:
            M, C, K = self.kept(k)
            N, stack = (2 * m + 1) * k, np.concatenate([M[..., None], C, K], axis=-1)
            offsets = harmonic_offsets(stack, m).transpose(4, 0, 2, 1, 3)
            self._hill[k, m] = np.ascontiguousarray(offsets).reshape(-1, N, N)
        return self._hill[k, m]

    def hill_tops(self, k: int, m: int) -> np.ndarray:
        """Largest entry modulus (1 + Pc + Pk,) of each of :meth:`hill_terms`."""
        if (k, m) not in self._hill_tops:
            self._hill_tops[k, m] = np.abs(self.hill_terms(k, m)).max(axis=(1, 2))
        return self._hill_tops[k, m]

    def kept(self, k: int) -> tuple[np.ndarray, ...]:
        """Spectra M, C, K of the k-mode model (2K+1, k, k[, P])."""
        if k not in self._kept:
            self._kept[k] = tuple(modal_spectrum(X, self.modes.shapes[:, :k]) for X in self.model._power_spectra[:3])
        return self._kept[k]

    def ladder(self, k: int) -> _Ladder:
        """The ladder of the k-mode model (:meth:`kept`)."""
        if k not in self._ladders:
            self._ladders[k] = _Ladder(*self.kept(k), LADDER_TOL)
        return self._ladders[k]

    def truncated_blocks(self, w: float, k: int) -> tuple[np.ndarray, np.ndarray | None]:
        """The mean truncated blocks at speed w side by side and transposed, and the mass's
        diagonal, for :func:`~periodyn.stability.schur.truncated_solve`: [C_hh^T, K_hh^T]
        (n-k, 2(n-k)) and diag M_hh (n-k,) where M_hh is diagonal to MASS_DIAGONAL (the
        modes are M-orthonormal: its off-diagonal is the rounding of the mean), else
        [M_hh^T, C_hh^T, K_hh^T] and None (their omega-power terms kept contiguous per k)."""
        if k not in self._truncated:
            M, C, K = (np.ascontiguousarray(X[..., k:, k:].swapaxes(-1, -2)) for X in self._means)
            diagonal = np.diag(M).copy()
            if np.abs(M - np.diag(diagonal)).max(initial=0.0) <= MASS_DIAGONAL * np.abs(diagonal).min(initial=np.inf):
                M = diagonal
            self._truncated[k] = (M, C, K)
        M, C, K = self._truncated[k]
        blocks = [np.tensordot(w ** np.arange(len(C)), C, 1), np.tensordot(w ** np.arange(len(K)), K, 1)]
        return (np.concatenate(blocks, axis=1), M) if M.ndim == 1 else (np.concatenate([M] + blocks, axis=1), None)

    def truncated_exponents(self, w: float, k: int) -> np.ndarray:
        """Diagonal mean estimates (2(n-k),) of the exponents of the truncated modes."""
        h = np.arange(k, self.n)
        mm, C, K = (X[..., h, h] for X in self._means)  # the mean diagonals, ([P, ]n-k)
        c, kk = w ** np.arange(len(C)) @ C, w ** np.arange(len(K)) @ K
        disc = np.sqrt((c * c - 4 * mm * kk).astype(complex))
        return np.concatenate([(-c + disc) / (2 * mm), (-c - disc) / (2 * mm)])

    def mean_exponents(self, w: float, k: int) -> np.ndarray:
        """Exponents (2k,) of the kept modes' mean system at speed w (the representatives'
        first guess: a Floquet exponent lies near one of them)."""
        M, C, K = (np.tensordot(w ** np.arange(len(X)), X[:, :k, :k], 1) for X in (self._means[0][None], *self._means[1:]))
        A = np.block([[np.zeros((k, k)), np.eye(k)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
        return np.linalg.eigvals(A)

    def correction(self, lam: complex, w: float, m: int, k: int) -> tuple[complex, complex, str]:
        """(centred exponent, d_lambda, "") of the reduced exponent lam at speed w with m
        harmonics and k kept modes, or (lam, nan, why) where it is not determined."""
        terms = self.hill_terms(k, m)
        Pc = self.powers[0]
        M = terms[0]
        C = np.tensordot(w ** np.arange(Pc), terms[1: 1 + Pc], 1)
        K = np.tensordot(w ** np.arange(len(terms) - 1 - Pc), terms[1 + Pc:], 1)
        a = np.arange(-m, m + 1)
        nu = self.mean_exponents(w, k)
        j = np.rint((nu.imag - lam.imag) / w)
        lam = lam + 1j * w * j[np.argmin(np.abs(lam + 1j * w * j - nu))]
        centred = centred_null_vectors(M, C, K, lam, w, k)
        if centred is None:
            return lam, np.nan, "no centred reduced-Hill null vector"
        lam, x, y = centred
        s = lam + 1j * a * w  # s_b per column harmonic b
        sc = np.repeat(s, k)
        energy = (np.abs(x) ** 2).sum(axis=1)
        if (energy[0] + energy[-1]) / energy.sum() > EDGE_MAX:
            return lam, np.nan, "the reduced-Hill null vector reaches the outermost harmonics"
        xs, yc = x.reshape(-1), np.conj(y.reshape(-1))
        denom = yc @ (M @ (2 * sc * xs)) + yc @ (C @ xs)  # y^H Q' x, Q' = 2 M s + C
        tops = self.hill_tops(k, m)  # max|Q'| <= 2 max|s| max|M| + sum_p w^p max|C_p|
        if abs(denom) < DOUBLE_TOL * (2 * np.abs(s).max() * tops[0] + w ** np.arange(Pc) @ tops[1: 1 + Pc]):
            return lam, np.nan, "near a double exponent (y^H Q' x -> 0)"
        r, sh = self._coupled(w, k, m, s, x, y)  # s_h[b] = sum_a y_a^H Q_lh[a, b]
        z = truncated_solve(*self.truncated_blocks(w, k), s, r)
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


def reduced_costs(stage, w: np.ndarray) -> np.ndarray:
    """Estimated seconds (S,) of the method "reduced" at the speeds w (S,) rad/s where "auto"
    takes it, inf elsewhere. It takes it on models of at least AUTO_MIN_COORDINATES
    coordinates (positive definite mean mass) whose guarded mode count k leaves modes out,
    where the reduced ladder's first comparison plus the correction (CORRECTION_COST) is
    estimated cheaper than (n/k)^3 times that first comparison (a lower bound of the full
    ladder's: more coordinates, at least as stiff); the estimate is LADDER_CLIMB times the
    first comparison plus the correction."""
    n, out = stage.n, np.full(w.size, np.inf)
    if n < AUTO_MIN_COORDINATES:
        return out
    try:
        R = stage.prepared("reduced")
    except (np.linalg.LinAlgError, ValueError):  # no positive definite mean mass: no mean modes
        return out
    k = np.array([guarded_modes(R.modes, START_MODES, stage.m, wi) for wi in w])
    for kk in np.unique(k[k < n]):
        group = np.nonzero(k == kk)[0]
        first = R.ladder(int(kk)).first_cost(w[group])
        correction = CORRECTION_COST[0] * ((2 * stage.m + 1) * kk) ** 3 + CORRECTION_COST[1]
        out[group] = np.where(first + correction < (n / kk) ** 3 * first, LADDER_CLIMB * first + correction, np.inf)
    return out


def reduced_pays(stage, w: np.ndarray) -> np.ndarray:
    """Speeds w (S,) where "auto" takes the method "reduced" (:func:`reduced_costs`)."""
    return np.isfinite(reduced_costs(stage, w))


def reduced_first(stage, w: np.ndarray, full):
    """"auto" per speed in a sweep: the reduced method where :func:`reduced_pays`, and
    ``full(stage, w)`` -> (names, reasons, exponents, solved) (the full model's rule) at the
    other speeds and where it did not certify; the records of the reduced method (their
    fill values elsewhere)."""
    S = w.size
    use = reduced_pays(stage, w)
    records = {"reduced_modes": np.zeros(S, np.int32), "reduced_correction": np.full(S, np.nan),
               "stability_error_bound": np.full(S, np.nan)}
    names, reasons = np.full(S, "reduced", dtype=object), np.full(S, "", dtype=object)
    exps, solved = np.full((S, 2 * stage.n), np.nan + 0j), np.zeros(S, bool)
    if use.any():
        at = np.nonzero(use)[0]
        exps[at], solved[at], reasons[at], rec = stage.prepared("reduced").solve(w[at], stage.m)
        for name, values in rec.items():
            records[name][at] = values
    rest = np.nonzero(~solved)[0]
    if rest.size:
        names[rest], why, exps[rest], solved[rest] = full(stage, w[rest])
        reasons[rest] = [f"{r}; {y}" if r else y for r, y in zip(reasons[rest], why)]
    return names, reasons, exps, solved, records
