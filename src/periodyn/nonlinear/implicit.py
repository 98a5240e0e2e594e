"""Shooting of element models on a fixed-step implicit one-period map, entirely in Numba
(``periodyn.shooting(element_dae(model), omega, integrator="implicit")``).

The period is integrated in N steps of the trapezoidal rule (:mod:`periodyn.kernels.solvers.implicit`)
with simplified Newton per step and the analytic acceleration Jacobians -M̄⁻¹K̄, -M̄⁻¹C̄ of the
element kernel; the monodromy matrix is that of the discrete map, propagated with the
converged step Jacobians, so shooting Newton gets the exact Jacobian of the map it solves.

Why the trapezoidal rule: it is A-stable (the stiff bending modes of a flexible member
need no step restriction) and, unlike generalized-alpha or HHT, adds no numerical
damping: an undamped mode keeps |multiplier| = 1 and a damped mode keeps its decay rate
to O((omega_i h)^2), so the Floquet multipliers of the discrete map stay on the right side
of the unit circle at the steps affordable here. Being symmetric, its periodic orbit
expands in even powers of h, c_N = c + K h^2 + O(h^4) for every harmonic c, so two orbits,
on N and N/2 steps, give

- the Richardson estimate |c_N - c_{N/2}| / 3 of the error of the N-step harmonics:
  ``PeriodicSolution.discretization_error`` is its maximum over all harmonics and
  coordinates relative to the largest |c|;
- the extrapolated harmonics c_N + (c_N - c_{N/2}) / 3, error O(h^4), which are the ones
  returned (and the multipliers of the extrapolated monodromy S_N + (S_N - S_{N/2}) / 3).

Measured on the non-linear slider-crank at 150 rad/s against DOP853 shooting at rtol
1e-11, N = 128, 256, 512, 1024: the N-step error falls at order 1.91, 1.98, 1.99 and is
1.36, 1.09, 1.02, 1.005 times the estimate (the rest is the h^4 term, so the estimate
alone is not a bound); the extrapolated error falls at order 3.6, 3.9, 4.0 and is 0.37,
0.089, 0.022, 0.0055 times the estimate. The estimate therefore bounds the error of the
returned harmonics, by a margin that grows as 4^k with the steps (N >= 256 for a tenfold
margin on this model). Multiplier error of the extrapolated monodromy: 2.9e-3 at N = 256,
1.8e-4 at N = 512 (|mu| = 0.49).
"""

from __future__ import annotations

import numpy as np

from ..errors import ConvergenceError, InputError
from ..stability.floquet import FloquetExponents
from ..kernels.solvers import implicit as kernel
from ..model.kinematics import MAX_HALVINGS, NEWTON_MAX_ITER
from ..periodic import PeriodicSolution
from ..numerics.spectra import fourier_coefficients
from ..numerics.newton_iteration import newton
from ..numerics.options import STEPS  # default steps per period (its comment: the accuracy it gives)

__all__ = ["ImplicitMap", "ImplicitProblem", "implicit_shooting", "STEPS"]

STEP_TOL = 1e-10  # Newton per step: max|G| <= STEP_TOL (1 + max|y|)
STEP_MAX_ITER = 12


class ImplicitMap:
    """One-period trapezoidal map y(0) -> y(T) at driving frequency omega (rad/s),
    T = 2 pi nu / omega, with its exact derivative, of an element model
    (``element_dae``) or a rheo-linear system (``rheo_linear_dae``)."""

    def __init__(self, system, omega: float, subharmonic: int = 1):
        self.eq = getattr(system, "equations", None)
        self.linear = getattr(system, "rheo_linear", None)
        if self.linear is None and (self.eq is None or not hasattr(self.eq, "configurations")):
            raise InputError(f"integrator='implicit' integrates element models (periodyn.element_dae) and rheo-linear "
                             f"systems (rheo_linear_dae); '{system.name}' is neither: use method='DOP853', 'Radau' or 'BDF'")
        if self.eq is not None and self.linear is None and not self.eq.model.uniform:
            raise InputError(f"integrator='implicit' integrates element models driven at constant speed; '{system.name}' "
                             "has inputs or loads that are functions of the driving angle: use method='DOP853' "
                             "(or 'Radau' / 'BDF' for stiff models)")
        if self.linear is not None and not np.isclose(omega, self.linear.omega, rtol=1e-12):
            raise InputError(f"omega={omega!r} differs from the rheo-linear system's own omega {self.linear.omega!r}")
        self.n = system.n
        self.omega, self.T = float(omega), 2 * np.pi * int(subharmonic) / float(omega)
        self.evaluations = 0
        self._last: dict[int, tuple] = {}  # steps -> (y0, Y, S) of the latest map with that many steps

    def _data(self, y0):
        if self.linear is not None:
            S = self.linear.inverse_mass_spectra
            return (self.omega, *(np.ascontiguousarray(a, dtype=complex) for a in (S.damping, S.stiffness, S.force)))
        eq, nd = self.eq, self.n
        Q, Qd = eq.inputs(y0[None, :nd], y0[None, nd:], np.zeros(1), self.omega)
        X, Qx, FQ = (np.ascontiguousarray(a[:1]).copy() for a in eq.configurations.start(Q))
        return (eq.model.arrays, np.asarray(eq.rates, float), self.omega, Q, Qd, np.zeros_like(Qd),
                np.zeros((1, eq.model.n_coordinates)), X, Qx, FQ, eq.configurations.tol,
                NEWTON_MAX_ITER, MAX_HALVINGS, np.empty((1, nd)), np.empty((1, nd, nd)), np.empty((1, nd, nd)),
                np.zeros((1, 2)))

    def __call__(self, y0, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """States Y (steps + 1, 2n) at k T / steps from y0 (2n,) and the monodromy S (2n, 2n)
        of the discrete map. Raises ConvergenceError when a step fails."""
        y0 = np.ascontiguousarray(y0, dtype=float)
        last = self._last.get(steps)
        if last is not None and np.array_equal(last[0], y0):
            return last[1:]
        Y = np.empty((steps + 1, 2 * self.n))
        S = np.empty((2 * self.n, 2 * self.n))
        counts = np.zeros(2, np.int64)
        done = kernel.period_map(self._data(y0), y0, 0.0, self.T, int(steps), STEP_TOL,
                                 STEP_MAX_ITER, Y, S, counts)
        self.evaluations += int(counts[0])
        if done < steps:
            raise ConvergenceError(f"implicit step {done + 1} of {steps} at omega={self.omega:.6g} rad/s failed (no "
                                   "configuration or Newton did not converge); use more steps or a better start",
                                   float("nan"), done)
        self._last[steps] = (y0.copy(), Y, S)
        return Y, S

    def newton(self, s, steps: int, tol: float, max_iter: int):
        """Shooting Newton on R(s) = y(T) - s; NewtonResult (jacobian = S - I). Raises
        ConvergenceError with the shooting residual and iteration count reached, also when
        the map itself fails at an iterate (then the count is of residual evaluations)."""
        done = []  # max|R| of every residual evaluated

        def equations(x):
            try:
                Y, S = self(x, steps)
            except ConvergenceError as exc:
                last, k = (done[-1] if done else float("nan")), len(done)
                raise ConvergenceError(f"implicit shooting at omega={self.omega:.6g} rad/s: {exc}, after {k} "
                                       f"residual evaluations (last residual {last:.3g})", last, k) from None
            done.append(float(np.max(np.abs(Y[-1] - x))))
            return Y[-1] - x, S - np.eye(x.size)

        return newton(equations, s, tol=tol, max_iter=max_iter, backtrack=9, accept=2.0,
                      label=f"implicit shooting at omega={self.omega:.6g} rad/s ({steps} steps)",
                      hint="start from a better guess (IHB solution or settle_periods)")


def implicit_shooting(system, omega: float, q, qd, *, subharmonic: int = 1, steps: int = STEPS, settle_periods: int = 0,
                      tol: float = 1e-9, max_iter: int = 30, samples: int = 128, params=None) -> PeriodicSolution:
    """Periodic solution of an element model by shooting on the trapezoidal map with
    ``steps`` (even) steps per period from the state (q, qd) (n,) at t = 0; Newton first
    on steps / 2, then on steps from that orbit. Harmonics up to min((samples - 1) // 2,
    steps // 4 - 1) and multipliers Richardson-extrapolated from the two orbits, with the
    error estimate of the module docstring."""
    steps = int(steps)
    if steps < 8 or steps % 2:
        raise InputError(f"steps must be an even number of steps per period >= 8, got {steps}")
    pmap = ImplicitMap(system, omega, subharmonic)
    s = np.concatenate([np.asarray(q, float).reshape(-1), np.asarray(qd, float).reshape(-1)])
    for _ in range(int(settle_periods)):
        s = pmap(s, steps // 2)[0][-1]
    coarse = pmap.newton(s, steps // 2, tol, max_iter)
    res = pmap.newton(coarse.x, steps, tol, max_iter)
    return _extrapolated(system, pmap, coarse.x, res.x, steps, samples, res.residual,
                         coarse.iterations + res.iterations, params)


def _extrapolated(system, pmap, xc, x, steps, samples, residual, iterations, params, harmonics=None):
    """PeriodicSolution from the orbits xc on steps / 2 and x on steps (module docstring):
    extrapolated harmonics (H = harmonics, or min((samples - 1) // 2, steps // 4 - 1)) and
    multipliers, with the error estimate."""
    (Yc, Sc), (Y, S) = pmap(xc, steps // 2), pmap(x, steps)
    n, H = system.n, min((int(samples) - 1) // 2, steps // 4 - 1)
    H = H if harmonics is None else min(H, int(harmonics))
    fine, rough = (fourier_coefficients(Z[:-1, :n], H) for Z in (Y, Yc))
    harmonics = fine + (fine - rough) / 3
    scale = np.abs(harmonics).max()
    error = float(np.abs(fine - rough).max() / 3 / scale) if scale > 0 else 0.0
    nu = int(round(pmap.T * pmap.omega / (2 * np.pi)))
    stability = FloquetExponents.from_multipliers(np.linalg.eigvals(S + (S - Sc) / 3), pmap.omega, "shooting", nu)
    return PeriodicSolution(pmap.omega, harmonics, None, system.coordinate_names, system.coordinate_names,
                            float(residual), iterations=int(iterations), method="shooting",
                            subharmonic=nu, lambda_harmonics=np.zeros((2 * H + 1, 0), complex),
                            stability=stability, parameters=dict(system.parameters if params is None else params),
                            discretization_error=error)


class ImplicitProblem:
    """Shooting residual R(X, omega) = y(T) - X (2n,) of the ``steps``-step trapezoidal map
    and its exact Jacobian S - I, for continuation in omega (``continuation(...,
    method="shooting")`` of element models); the maps of the latest speeds are kept. A
    recorded point also solves the steps / 2 map from it and is returned extrapolated, as
    by :func:`implicit_shooting` (the same solution to the Newton tolerance)."""

    def __init__(self, system, subharmonic: int = 1, steps: int = STEPS, samples: int = 128, tol: float = 1e-9):
        if int(steps) < 8 or int(steps) % 2:
            raise InputError(f"steps must be an even number of steps per period >= 8, got {steps}")
        ImplicitMap(system, 1.0, subharmonic)  # refuses systems it cannot integrate
        self.system, self.nu, self.steps, self.p, self.tol = system, int(subharmonic), int(steps), int(samples), tol
        self.parameter = None
        self._maps: dict[float, ImplicitMap] = {}

    def map(self, omega) -> ImplicitMap:
        """The one-period map at omega (rad/s), reused while omega recurs."""
        key = float(omega)
        if key not in self._maps:
            if len(self._maps) > 4:
                self._maps.pop(next(iter(self._maps)))
            self._maps[key] = ImplicitMap(self.system, key, self.nu)
        return self._maps[key]

    def state(self, q, qd) -> np.ndarray:
        return np.concatenate([np.asarray(q, float).reshape(-1), np.asarray(qd, float).reshape(-1)])

    def equations(self, X, omega, params=None):
        Y, S = self.map(omega)(X, self.steps)
        return Y[-1] - X, S - np.eye(X.size)

    def residual(self, X, omega, params=None) -> np.ndarray:
        return self.map(omega)(X, self.steps)[0][-1] - X

    def newton(self, X, omega, params=None, tol=1e-9, max_iter=30):
        return self.map(omega).newton(np.asarray(X, float), self.steps, tol, max_iter)

    def solution(self, X, omega, params, residual, iterations, harmonics=None) -> PeriodicSolution:
        """The recorded orbit (class docstring); raises ConvergenceError when the coarse map fails."""
        pmap = self.map(omega)
        xc = pmap.newton(np.asarray(X, float), self.steps // 2, self.tol, 30).x
        return _extrapolated(self.system, pmap, xc, X, self.steps, self.p, residual, iterations, params, harmonics)
