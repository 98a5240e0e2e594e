"""Time-domain solutions of rheo-linear systems: the monodromy matrix and the direct
integration of ``M(t) q'' + C(t) q' + K(t) q = f(t)``.

Two monodromy integrators:
* the reference, DOP853 through the one integrator wrapper (``periodyn.nonlinear.integrate.solve``)
  at rtol 1e-11 on the exact callables (systems built with
  ``RheoLinear.from_functions``) or on the Fourier series of the samples;
* ``magnus``: the fixed-step 4th-order Magnus integrator with two Gauss points per step,
  ``Phi <- exp(h/2 (A1 + A2) + sqrt(3)/12 h^2 [A2, A1]) Phi``, which treats stiff, heavily
  damped element modes exactly in the frozen part and costs one batch of small matrix
  exponentials per speed (used by fast stability sweeps and the DAE stability analysis).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ConvergenceError
from .floquet import STABILITY_TOL, FloquetExponents
from .kernels.floquet import magnus_monodromies, magnus_product
from .nonlinear.integrate import solve
from .nonlinear.linear import ode
from .nonlinear.variational import flow
from .spectra import synthesize
from .system import RheoLinear

__all__ = ["first_order_matrix", "monodromy_matrix", "monodromy_exponents", "integrate", "gauss_angles",
           "magnus_terms", "magnus_transition", "magnus_steps", "monodromy_exponent_array", "MagnusLadder",
           "MagnusEstimate", "half_period_signs"]

RTOL, ATOL = 1e-11, 1e-13


def _coefficients(system: RheoLinear):
    """Callable t -> (M, C, K, f) at time t (s)."""
    if system.functions is not None:
        Mf, Cf, Kf, ff = system.functions
        n = system.n

        def at(t):
            return (np.asarray(Mf(t), float).reshape(n, n), np.asarray(Cf(t), float).reshape(n, n),
                    np.asarray(Kf(t), float).reshape(n, n), np.asarray(ff(t), float).reshape(n))

        return at
    S = system.spectra
    K = (S.mass.shape[0] - 1) // 2
    k = np.arange(-K, K + 1)

    def at(t):
        e = np.exp(1j * k * system.omega * t)
        return tuple(np.tensordot(e, X, 1).real for X in (S.mass, S.damping, S.stiffness, S.force))

    return at


def first_order_matrix(system: RheoLinear):
    """Callables t -> A(t) (2n, 2n) and t -> b(t) (2n,) of y' = A y + b, y = [q, q']."""
    coeff = _coefficients(system)
    n = system.n

    def A_b(t):
        M, C, K, f = coeff(t)
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        A[n:, :n] = -np.linalg.solve(M, K)
        A[n:, n:] = -np.linalg.solve(M, C)
        b = np.concatenate([np.zeros(n), np.linalg.solve(M, f)])
        return A, b

    return A_b


def _free_motion(system: RheoLinear):
    """The unforced system ``q'' = -M^-1 (C q' + K q)`` as an ODE ``DAE`` (unit mass),
    evaluated from the exact callables when the system has them, else from its spectra."""
    coeff = _coefficients(system)
    n = system.n
    last = [None, None]  # the flow asks for the force and its Jacobians at the same times

    def jacobians(q, qd, t, omega, P):
        t = np.asarray(t, float).reshape(-1)
        if last[0] is None or not np.array_equal(last[0], t):
            Kq, Kv = np.empty((t.size, n, n)), np.empty((t.size, n, n))
            for i, ti in enumerate(t):
                M, C, K, _ = coeff(float(ti))
                Kq[i], Kv[i] = -np.linalg.solve(M, K), -np.linalg.solve(M, C)
            last[:] = t.copy(), (Kq, Kv)
        return last[1]

    def force(q, qd, t, omega, P):
        Kq, Kv = jacobians(q, qd, t, omega, P)
        return np.einsum("pij,pj->pi", Kq, q) + np.einsum("pij,pj->pi", Kv, qd)

    return ode(n, force, jacobians, system.coordinate_names, "free_motion")


def monodromy_matrix(system: RheoLinear) -> np.ndarray:
    """Fundamental matrix after one period, Phi(T) with Phi(0) = I, (2n, 2n): the
    variational flow (:func:`periodyn.nonlinear.variational.flow`, the one monodromy of
    linear and non-linear problems) of the unforced system from y = 0 along the 2n unit
    directions, DOP853 at rtol 1e-11, atol 1e-13."""
    m2 = 2 * system.n
    out = flow(_free_motion(system), system.omega, np.zeros(m2), 0.0, 2.0 * np.pi, directions=np.eye(m2)[None],
               rtol=RTOL, atol=ATOL)
    return out.columns[0]


def magnus_steps(samples: int) -> int:
    """Default Magnus steps per period for coefficients sampled p times: max(128, 2p)."""
    return max(128, 2 * samples)


def gauss_angles(steps: int, start: float = 0.0, stop: float = 2 * np.pi) -> np.ndarray:
    """Angles of the two Gauss points of each of ``steps`` equal steps, (2 steps,), rad."""
    g = np.sqrt(3) / 6
    frac = (np.arange(steps)[:, None] + np.array([0.5 - g, 0.5 + g])[None, :]).ravel() / steps
    return start + (stop - start) * frac


def magnus_terms(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray) -> tuple[np.ndarray, float]:
    """Terms of the balanced first-order system matrix for the Magnus kernels.

    mass (g, n, n), damping (g, n, n, Pc), stiffness (g, n, n, Pk) at g points, the last
    axis holding the coefficients of powers of omega. Returns terms (max(Pc, Pk), g, 2n, 2n)
    with ``A = sum_p omega^p terms[p]`` the matrix of y' = A y for y = (a q, q'), and the
    balancing scale a = sqrt(max ||M^-1 K_0||_inf) (1/s), which brings the stiff blocks to
    the same size (a similarity: the transition matrix of (q, q') is D^-1 Phi D,
    D = diag(a I, I), with the same eigenvalues)."""
    g, n = mass.shape[:2]
    Pc, Pk = damping.shape[-1], stiffness.shape[-1]
    MinvC = np.linalg.solve(mass, damping.reshape(g, n, n * Pc)).reshape(g, n, n, Pc)
    MinvK = np.linalg.solve(mass, stiffness.reshape(g, n, n * Pk)).reshape(g, n, n, Pk)
    top = float(np.abs(MinvK[..., 0]).sum(axis=2).max()) if g else 0.0
    a = np.sqrt(top) if top > 0 else 1.0
    terms = np.zeros((max(Pc, Pk), g, 2 * n, 2 * n))
    terms[0, :, :n, n:] = a * np.eye(n)
    terms[:Pk, :, n:, :n] = -np.moveaxis(MinvK, -1, 0) / a
    terms[:Pc, :, n:, n:] = -np.moveaxis(MinvC, -1, 0)
    return terms, a


def magnus_transition(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, h: float) -> np.ndarray:
    """Transition matrix (2n, 2n) of y' = A(t) y, y = (q, q'), over equal steps h (s).

    mass/damping/stiffness: (2 steps, n, n) at the two Gauss points of each step (see
    :func:`gauss_angles`); the jitted 4th-order Magnus kernel on the balanced system."""
    n = mass.shape[1]
    terms, a = magnus_terms(mass, damping[..., None], stiffness[..., None])
    phi = np.empty((2 * n, 2 * n))
    magnus_product(terms[0], float(h), phi)
    phi[:n, n:] /= a  # undo the balancing: Phi = D^-1 Phi_balanced D
    phi[n:, :n] *= a
    return phi


def monodromy_exponents(system: RheoLinear, method: str = "monodromy", steps: int | None = None):
    """Characteristic exponents from the eigenvalues of the monodromy matrix (principal
    logarithm, |Im| <= omega/2). method: "monodromy" (DOP853 reference) or "magnus"
    (``steps`` fixed steps, default :func:`magnus_steps`)."""
    if method == "magnus":
        steps = steps or magnus_steps(system.samples)
        theta = gauss_angles(steps)
        S = system.spectra
        Mg, Cg, Kg = (synthesize(X, theta) for X in (S.mass, S.damping, S.stiffness))
        Phi = magnus_transition(Mg, Cg, Kg, system.period / steps)
    else:
        Phi = monodromy_matrix(system)
    return exponents_from_monodromy(Phi, system.omega, method)


def exponents_from_monodromy(Phi: np.ndarray, omega: float, method: str):
    """FloquetExponents from a monodromy matrix (2n, 2n) at driving speed omega (rad/s)."""
    if not np.isfinite(Phi).all():
        raise ConvergenceError(f"the monodromy matrix ({method}) at omega = {omega:.6g} rad/s is not finite; "
                               "use method='monodromy' (adaptive steps) or check the model's coefficients")
    lam = monodromy_exponent_array(Phi[None], np.array([float(omega)]))[0]
    if np.isnan(lam).any():
        raise ConvergenceError(f"the monodromy matrix ({method}) at omega = {omega:.6g} rad/s is singular: a mode "
                               "decays by more than 1e-308 in one period, so its exponent is not determined; use "
                               "Hill's method (method='dense' or 'sparse') or check the model's damping")
    nan = np.full(lam.size, np.nan)
    return FloquetExponents(float(omega), lam, nan, nan, method)


def monodromy_exponent_array(Phi: np.ndarray, omegas: np.ndarray) -> np.ndarray:
    """Exponents (S, d) from monodromy matrices (S, d, d) at speeds omegas (S,) rad/s: the
    principal logarithms of the multipliers (|Im| <= omega/2), sorted by real then
    imaginary part. A row with a zero multiplier (the monodromy underflowed: a mode decays
    by more than the double range, 1e-308, in one period, so its exponent is not
    determined) is NaN."""
    mu = np.linalg.eigvals(Phi).astype(complex)
    ok = np.all(mu != 0, axis=-1)
    lam = np.full(mu.shape, np.nan + 0j)
    lam[ok] = np.log(mu[ok]) * (np.asarray(omegas, float)[ok, None] / (2 * np.pi))
    return np.take_along_axis(lam, np.lexsort((lam.imag, lam.real), axis=-1), -1)


def integrate(system: RheoLinear, y0, t) -> np.ndarray:
    """Direct solution y = [q, q'] of the forced linear equations from y(0) = y0 (2n,) at
    times t (s, increasing from 0) -> (len(t), 2n)."""
    A_b = first_order_matrix(system)
    t = np.asarray(t, dtype=float)

    def rhs(tt, y):
        A, b = A_b(tt)
        return A @ y + b

    return solve(rhs, (0.0, float(t[-1])), np.asarray(y0, dtype=float), t_eval=t, rtol=RTOL, atol=ATOL).y.T


def half_period_signs(*spectra: np.ndarray, rtol: float = 1e-12) -> np.ndarray | None:
    """Signs s (n,) of a half-period symmetry ``X(theta + pi) = P X(theta) P``, P = diag(s),
    of every coefficient, or None if there is none.

    spectra: two-sided coefficient spectra (2K+1, n, n) or (2K+1, n, n, P). Entry (i, j)
    may have odd harmonics only if s_i = -s_j and even ones only if s_i = s_j (entries
    below rtol times the largest of their array count as zero); s by 2-colouring. Then
    the monodromy is ``(P Phi(T/2))^2`` with P acting on both q and q'."""
    n = spectra[0].shape[1]
    odd, even = np.zeros((n, n), bool), np.zeros((n, n), bool)
    for X in spectra:
        mag = np.abs(X).reshape(X.shape[0], n, n, -1).max(axis=-1)
        big = mag > rtol * mag.max()
        k = np.arange(X.shape[0]) - (X.shape[0] - 1) // 2
        odd |= big[k % 2 == 1].any(axis=0)
        even |= big[k % 2 == 0].any(axis=0)
    odd, even = odd | odd.T, even | even.T
    if (odd & even).any():
        return None
    signs = np.zeros(n)
    for root in range(n):
        if signs[root]:
            continue
        signs[root], stack = 1.0, [root]
        while stack:
            i = stack.pop()
            for j in np.nonzero(odd[i] | even[i])[0]:
                want = -signs[i] if odd[i, j] else signs[i]
                if signs[j] == 0:
                    signs[j] = want
                    stack.append(j)
                elif signs[j] != want:
                    return None
    return signs


# Seconds per Magnus step ~ (6 + squarings) products of d x d matrices + a set-up (fitted on
# one core for d = 2..128: the jitted loops below d = 16, BLAS dgemm from there on)
_PRODUCT_RATE = (4.5e9, 1.2e10)  # flop/s of one product, below / from d = 16
_STEP_SETUP = 5.0e-7  # s per step


@dataclass(frozen=True, eq=False)
class MagnusEstimate:
    """Magnus monodromy exponents at S speeds with their error estimate.

    exponents (S, 2n) complex rad/s (principal values); accepted (S,) bool: the estimate
    certifies the result (else the speed needs another method); steps (S,) fine steps
    used (over the ladder's span: half a period for half-period-symmetric coefficients);
    error (S,) estimated error of log|mu| per period; margin (S,) distance of
    log max|mu| from the stability threshold."""

    exponents: np.ndarray
    accepted: np.ndarray
    steps: np.ndarray
    error: np.ndarray
    margin: np.ndarray


class MagnusLadder:
    """The 4th-order Magnus monodromy with step doubling, for one omega-polynomial model.

    mass (2K+1, n, n), damping (2K+1, n, n, Pc), stiffness (2K+1, n, n, Pk): two-sided
    spectra with omega powers last. At each speed, the multipliers from N and N/2 equal
    steps (N = START, 2 START, ...) are compared, with G = log max|mu|:
    ``e = max(|G_N - G_N/2|, max |sort|mu_N| - sort|mu_N/2|| / max|mu_N|)``. For the
    order-4 method the error of N steps is about e / 15 once the steps resolve the
    coefficients; e itself is used as the estimate, which also holds before that regime
    (the difference of two results bounds the error of the better one when the error at
    least halves per doubling; Richardson's e / 15 was seen to miss by 10x on the
    slider-crank). The largest multiplier is so certified in log|mu|, the others to
    e max|mu| (a strongly damped mode's multiplier far below the largest is resolved
    absolutely, not in its logarithm). A speed is accepted when e <= STABILITY_TOL
    max(1, |G_N|) (relative to a growth above 1 per period, where the verdict is clear) and
    the verdict cannot flip, ``|G_N - STABILITY_TOL| > e``; otherwise (also when the
    multipliers overflow: at low speeds the coarse steps span many vibration periods) N is
    doubled while the estimated cost stays within the speed's budget (and N <= LARGEST).

    When the coefficients have a half-period symmetry (:func:`half_period_signs`), the
    steps cover half a period and the monodromy is ``(P Phi(T/2))^2``: the same step
    length at half the cost.
    """

    START = 32
    LARGEST = 4096  # steps

    def __init__(self, mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray):
        self.spectra = (mass, damping, stiffness)
        self.n = mass.shape[1]
        self.signs = half_period_signs(mass, damping, stiffness)
        self.span = 2 * np.pi if self.signs is None else np.pi  # angle the steps cover, rad
        self._terms: dict[int, np.ndarray] = {}
        self.scale = self.terms(self.START)[1]

    def terms(self, steps: int) -> tuple[np.ndarray, float]:
        """Terms of the balanced system matrix at the Gauss angles of ``steps`` steps over
        the span; over half a period, term p is divided by 2^p so that the kernel, given
        twice the speed, takes steps of span / (omega steps) with the right matrix."""
        if steps not in self._terms:
            terms, a = magnus_terms(*(synthesize(X, gauss_angles(steps, 0.0, self.span)) for X in self.spectra))
            if self.signs is not None:
                terms = terms / (2.0 ** np.arange(terms.shape[0]))[:, None, None, None]
            self._terms[steps] = terms, a
        return self._terms[steps]

    def cost(self, omegas: np.ndarray, steps: int) -> np.ndarray:
        """Estimated seconds (S,) of one monodromy with ``steps`` steps at speeds omegas:
        the squarings of the exponentials follow the balanced generator's size,
        scale * 2 pi / (omega steps)."""
        d = 2 * self.n
        rho = self.scale * self.span / (np.asarray(omegas, float) * steps)
        squarings = np.maximum(0.0, np.ceil(np.log2(np.maximum(rho, 1e-300) / 4.0)))
        product = 2.0 * d**3 / _PRODUCT_RATE[int(d >= 16)]
        return steps * ((6.0 + squarings) * product + _STEP_SETUP)

    def first_cost(self, omegas: np.ndarray) -> np.ndarray:
        """Estimated seconds (S,) of the first comparison (START and START / 2 steps)."""
        return self.cost(omegas, self.START) + self.cost(omegas, self.START // 2)

    def _moduli(self, omegas: np.ndarray, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """Exponents (S, 2n) and sorted multiplier moduli (S, 2n) with ``steps`` steps
        (NaN where the monodromy matrix is not finite)."""
        Phi = np.empty((omegas.size, 2 * self.n, 2 * self.n))
        if self.signs is None:
            magnus_monodromies(self.terms(steps)[0], omegas, Phi)
        else:
            magnus_monodromies(self.terms(steps)[0], 2.0 * omegas, Phi)  # Phi(T/2), see terms()
            Phi *= np.concatenate([self.signs, self.signs])[:, None]
            with np.errstate(all="ignore"):  # an overflow is caught as non-finite below
                Phi = Phi @ Phi
        finite = np.isfinite(Phi).all(axis=(1, 2))
        exps = np.full((omegas.size, 2 * self.n), np.nan + 0j)
        exps[finite] = monodromy_exponent_array(Phi[finite], omegas[finite])
        with np.errstate(over="ignore"):  # a multiplier beyond the double range is inf: not accepted
            return exps, np.sort(np.exp(exps.real * (2 * np.pi / omegas)[:, None]), axis=1)

    def solve(self, omegas, budget) -> MagnusEstimate:
        """Exponents at speeds omegas (S,) rad/s, each speed doubling its steps while the
        spent estimated cost stays within budget (S,) s."""
        w = np.asarray(omegas, float)
        S, d = w.size, 2 * self.n
        out = MagnusEstimate(np.full((S, d), np.nan + 0j), np.zeros(S, bool), np.zeros(S, np.int64),
                             np.full(S, np.inf), np.full(S, np.nan))
        spent = self.cost(w, self.START // 2)
        pending = np.nonzero(spent + self.cost(w, self.START) <= np.asarray(budget, float))[0]
        _, coarse = self._moduli(w[pending], self.START // 2)
        steps = self.START
        while pending.size:
            spent[pending] += self.cost(w[pending], steps)
            exps, fine = self._moduli(w[pending], steps)
            with np.errstate(all="ignore"):  # non-finite multipliers: error NaN, not accepted
                top = np.log(fine[:, -1])
                error = np.maximum(np.abs(top - np.log(coarse[:, -1])), np.abs(fine - coarse).max(axis=1) / fine[:, -1])
                margin = np.abs(top - STABILITY_TOL)
                ok = (error <= STABILITY_TOL * np.maximum(1.0, np.abs(top))) & (margin > error)
            for name, value in (("exponents", exps), ("steps", steps), ("error", error), ("margin", margin)):
                getattr(out, name)[pending] = value
            out.accepted[pending] = ok
            # a non-finite result (steps far too long: the commutator term overflows) doubles too
            more = ~ok & (spent[pending] + self.cost(w[pending], 2 * steps) <= np.asarray(budget, float)[pending])
            more &= 2 * steps <= self.LARGEST
            pending, coarse, steps = pending[more], fine[more], 2 * steps
        return out
