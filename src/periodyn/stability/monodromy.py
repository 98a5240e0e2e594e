"""Time-domain solutions of rheo-linear systems: the monodromy matrix and the direct
integration of ``M(t) q'' + C(t) q' + K(t) q = f(t)``.

Two monodromy integrators:
* the reference, DOP853 through the one integrator wrapper (``periodyn.numerics.integration.solve``)
  at rtol 1e-11 on the exact callables (systems built with
  ``RheoLinear.from_functions``) or on the Fourier series of the samples;
* ``magnus``: the fixed-step 4th-order Magnus integrator with two Gauss points per step,
  ``Phi <- exp(h/2 (A1 + A2) + sqrt(3)/12 h^2 [A2, A1]) Phi``, which treats stiff, heavily
  damped element modes exactly in the frozen part and costs one batch of small matrix
  exponentials per speed (used by fast stability sweeps and the DAE stability analysis).
  It and the certified Magnus ladder of the stability method "auto" live in
  :mod:`periodyn.stability.magnus`.
"""

from __future__ import annotations

import numpy as np

from ..errors import ConvergenceError
from .floquet import FloquetExponents
from .hill import top_frequencies
from .magnus import gauss_angles, magnus_steps, magnus_transition, monodromy_exponent_array
from ..numerics.integration import solve
from ..dae import ode
from ..numerics.variational import flow
from ..numerics.spectra import StackedSpectra, real_basis
from ..system import RheoLinear

__all__ = ["first_order_matrix", "monodromy_matrix", "monodromy_exponents", "exponents_from_monodromy", "integrate"]

RTOL, ATOL = 1e-11, 1e-13
#: Most natural periods (of the mean system's highest vibration frequency) that one driving
#: period may span for the DOP853 monodromy: its cost grows with that count (elliptic pendulum:
#: 1.3 s at 10, 8 s at 1000), and at 1e-7 rad/s (1e7 of them) it would not return.
MAX_NATURAL_PERIODS = 1e4


def _coefficients(system: RheoLinear, forced: bool = True):
    """Callable t -> (M, C, K, f) at time t (s) ((M, C, K) when not ``forced``); from the
    spectra, all matrices come from one real product (:class:`periodyn.numerics.spectra.StackedSpectra`)."""
    n = system.n
    if system.functions is not None:
        Mf, Cf, Kf, ff = system.functions

        def at(t):
            out = (np.asarray(Mf(t), float).reshape(n, n), np.asarray(Cf(t), float).reshape(n, n),
                   np.asarray(Kf(t), float).reshape(n, n))
            return out + (np.asarray(ff(t), float).reshape(n),) if forced else out

        return at
    S = system.spectra
    stacked = StackedSpectra(S.mass, S.damping, S.stiffness, *[S.force] * forced)

    def at(t):
        values = real_basis(stacked.harmonics, system.omega * t) @ stacked.rows
        return tuple(v[0] for v in stacked.split(values))

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
    coeff = _coefficients(system, forced=False)
    n = system.n
    last = [None, None]  # the flow asks for the force and its Jacobians at the same times

    def jacobians(q, qd, t, omega, P):
        t = np.asarray(t, float).reshape(-1)
        if last[0] is None or not np.array_equal(last[0], t):
            KC = np.empty((t.size, n, 2 * n))
            for i, ti in enumerate(t):
                M, C, K = coeff(float(ti))
                KC[i] = -np.linalg.solve(M, np.concatenate([K, C], axis=1))
            last[:] = t.copy(), (KC[:, :, :n], KC[:, :, n:])
        return last[1]

    def force(q, qd, t, omega, P):
        Kq, Kv = jacobians(q, qd, t, omega, P)
        return np.einsum("pij,pj->pi", Kq, q) + np.einsum("pij,pj->pi", Kv, qd)

    return ode(n, force, jacobians, system.coordinate_names, "free_motion")


def monodromy_matrix(system: RheoLinear) -> np.ndarray:
    """Fundamental matrix after one period, Phi(T) with Phi(0) = I, (2n, 2n): the
    variational flow (:func:`periodyn.numerics.variational.flow`, the one monodromy of
    linear and non-linear problems) of the unforced system from y = 0 along the 2n unit
    directions, DOP853 at rtol 1e-11, atol 1e-13."""
    m2 = 2 * system.n
    out = flow(_free_motion(system), system.omega, np.zeros(m2), 0.0, 2.0 * np.pi, directions=np.eye(m2)[None],
               rtol=RTOL, atol=ATOL)
    return out.columns[0]


def monodromy_exponents(system: RheoLinear, method: str = "monodromy", steps: int | None = None):
    """Characteristic exponents from the eigenvalues of the monodromy matrix (principal
    logarithm, |Im| <= omega/2). method: "monodromy" (DOP853 reference) or "magnus"
    (``steps`` fixed steps, default :func:`magnus_steps`)."""
    if method == "magnus":
        steps = steps or magnus_steps(system.samples)
        theta = gauss_angles(steps)
        S = system.spectra
        Mg, Cg, Kg = StackedSpectra(S.mass, S.damping, S.stiffness).at(theta)
        Phi = magnus_transition(Mg, Cg, Kg, system.period / steps)
    else:
        _check_span(system)
        Phi = monodromy_matrix(system)
    return exponents_from_monodromy(Phi, system.omega, method)


def _check_span(system: RheoLinear) -> None:
    """Refuse (ConvergenceError, a failed point in a sweep) a DOP853 monodromy whose period
    spans more than MAX_NATURAL_PERIODS periods of the mean system's highest frequency."""
    S = system.spectra
    K = (S.mass.shape[0] - 1) // 2
    top = float(top_frequencies(S.stiffness[K][None], S.damping[K][None], S.mass[K])[0])
    spans = top * system.period / (2 * np.pi)
    if spans > MAX_NATURAL_PERIODS:
        raise ConvergenceError(
            f"the monodromy (DOP853) at omega = {system.omega:.6g} rad/s would integrate {spans:.3g} natural periods "
            f"(highest frequency {top:.4g} rad/s) over one driving period, more than {MAX_NATURAL_PERIODS:g}; it "
            "would not finish: use Hill's method (method='dense' or 'sparse', with enough harmonics) or a higher speed")


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


def integrate(system: RheoLinear, y0, t) -> np.ndarray:
    """Direct solution y = [q, q'] of the forced linear equations from y(0) = y0 (2n,) at
    times t (s, increasing from 0) -> (len(t), 2n)."""
    A_b = first_order_matrix(system)
    t = np.asarray(t, dtype=float)

    def rhs(tt, y):
        A, b = A_b(tt)
        return A @ y + b

    return solve(rhs, (0.0, float(t[-1])), np.asarray(y0, dtype=float), t_eval=t, rtol=RTOL, atol=ATOL).y.T
