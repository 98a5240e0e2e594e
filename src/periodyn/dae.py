"""The DAE model ``M(q) q'' + Phi_q(q, t)^T lambda = f(q, q', t)``, ``Phi(q, t) = 0``.

:class:`DAE` stores *batch* evaluators: every method takes a leading batch axis
(time samples of one orbit, or trajectories integrated together) and returns arrays with
that axis first. Users build one from per-point callables with ``DAE(...)``; the planar
rigid-body builder (``periodyn.model.rigid2d``) supplies jitted batch kernels through
:meth:`DAE.from_batch`.

Units: SI (m, rad, kg, N, N m, s); omega in rad/s.
Parameters: ``parameters`` is a dict of named scalars (forcing amplitude, base amplitude,
...). When it is given, user callables receive it as a last argument, e.g.
``force(q, qd, t, omega, params)``; without it the DESIGN.md signatures
``force(q, qd, t, omega)``, ``constraint(q, t, omega)`` are used. ``with_parameters``
returns a copy with changed values (used by parameter continuation).

:func:`ode` and :func:`rheo_linear_dae` give ODE problems (m = 0, unit mass), the latter a
rheo-linear system ``q'' = r(t) - P(t) q' - Q(t) q`` (P = M⁻¹C, Q = M⁻¹K, r = M⁻¹f, the
paper's form 16, evaluated at any t from the trigonometric interpolation of the samples), so
the linearized equations are integrated and shot like the non-linear ones.
"""

from __future__ import annotations

import copy
import warnings
from typing import Callable, Mapping, Sequence

import numpy as np

from .errors import InputError
from .numerics.spectra import StackedSpectra

__all__ = ["DAE", "ode", "rheo_linear_dae"]

_CSTEP = 1e-30  # complex-step size: derivatives exact to round-off, no truncation error
_FD_REL = 1e-5  # central-difference step (relative) for the Hessian of a derived constraint Jacobian


def complex_step(fun, x) -> np.ndarray:
    """Jacobian d fun / d x (..., n) of a real function of x (n,) that accepts complex x,
    by the complex step (exact to round-off)."""
    cols = []
    for j in range(x.shape[0]):
        xc = x.astype(complex)
        xc[j] += 1j * _CSTEP
        cols.append(np.asarray(fun(xc)).imag / _CSTEP)
    return np.stack(cols, axis=-1)


def _refuse_real_only(build, what: str, fix: str) -> None:
    """Call build() once; a callable that drops the imaginary part of its argument is refused."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", np.exceptions.ComplexWarning)
            build()
    except (TypeError, np.exceptions.ComplexWarning) as exc:
        raise InputError(f"{what} does not accept complex arguments, so its Jacobian cannot be formed by the "
                         f"complex step ({exc}); pass {fix}") from None


class DAE:
    """Index-3 DAE of a driven mechanism (or an ODE when ``m == 0``).

    ``DAE(mass, force, constraint=None, ...)`` builds one from per-point callables (see
    :func:`_user_fields` for every option); :meth:`from_batch` from batch evaluators.

    Batch evaluators (p = batch size; params is a mapping):
      mass(q (p,n)) -> (p,n,n); force(q, qd, t, omega, params) -> (p,n);
      force_jacobians(...) -> (df/dq, df/dq') each (p,n,n);
      mass_jacobian(q, a) -> d(M(q) a)/dq (p,n,n), or None for a constant mass;
      constraint(q, t, omega, params) -> (p,m); constraint_jacobian(...) -> (p,m,n);
      constraint_hessian(q, lam (p,m), t, omega, params) -> sum_k lam_k Phi_k,qq (p,n,n);
      constraint_rates(q, qd, t, omega, params) -> (Phi_t, gamma) each (p,m), with
      ``Phi_q q'' = gamma`` (needed for time integration and shooting only).
    q0: (n,) reference configuration (Newton's starting point, close to Phi = 0).
    phase_forcing: the force depends on omega and t only through omega t (see
    :func:`_user_fields`).
    """

    n: int
    m: int

    def __init__(self, mass, force, constraint=None, **options):
        self.__dict__.update(_user_fields(mass, force, constraint, **options))

    @classmethod
    def from_batch(cls, *, n: int, m: int, mass: Callable, force: Callable, force_jacobians: Callable,
                   constraint: Callable, constraint_jacobian: Callable, constraint_hessian: Callable,
                   constraint_rates: Callable | None, mass_jacobian: Callable | None = None, q0=None,
                   parameters: Mapping[str, float] | None = None, coordinate_names: Sequence[str] | None = None,
                   constraint_names: Sequence[str] | None = None, name: str = "dae",
                   phase_forcing: bool = False) -> "DAE":
        """Build directly from batch evaluators (see the class docstring)."""
        obj = object.__new__(cls)
        obj.__dict__.update(
            n=int(n), m=int(m), mass=mass, force=force, force_jacobians=force_jacobians, constraint=constraint,
            constraint_jacobian=constraint_jacobian, constraint_hessian=constraint_hessian,
            constraint_rates=constraint_rates, mass_jacobian=mass_jacobian,
            q0=np.zeros(n) if q0 is None else np.asarray(q0, dtype=float).reshape(n).copy(),
            parameters=dict(parameters or {}),
            coordinate_names=tuple(coordinate_names) if coordinate_names is not None else tuple(f"q{i}" for i in range(n)),
            constraint_names=tuple(constraint_names) if constraint_names is not None else tuple(f"lambda{i}" for i in range(m)),
            name=name, phase_forcing=bool(phase_forcing))
        return obj

    def with_parameters(self, **values: float) -> "DAE":
        """Copy with some parameters changed; unknown names are refused."""
        unknown = set(values) - set(self.parameters)
        if unknown:
            raise InputError(f"unknown parameter(s) {sorted(unknown)}; this model has {sorted(self.parameters)}")
        obj = copy.copy(self)
        obj.parameters = dict(self.parameters, **{k: float(v) for k, v in values.items()})
        return obj

    def __repr__(self) -> str:
        return f"DAE(name={self.name!r}, n={self.n}, m={self.m}, parameters={self.parameters})"


def _finite_real(name: str, value, shape=lambda a: a) -> np.ndarray:
    """``shape(value)`` as a float array; InputError naming ``name`` when it is complex,
    not numeric, or has NaN or inf entries (they would be solved as another system)."""
    a = np.asarray(value)
    if np.iscomplexobj(a) or a.dtype == bool or not np.issubdtype(a.dtype, np.number):
        raise InputError(f"{name} must be a real numeric array, got {a.dtype} values: {value!r}")
    a = shape(a.astype(float))
    if not np.isfinite(a).all():
        raise InputError(f"{name} has NaN or inf entries: {a!r}; every entry must be a finite number (SI units)")
    return a


def _user_fields(mass, force, constraint=None, *, n: int | None = None, force_jacobian=None,
              constraint_jacobian=None, constraint_hessian=None, constraint_rates=None,
              mass_jacobian=None, parameters: Mapping[str, float] | None = None, q0=None,
              coordinate_names: Sequence[str] | None = None, constraint_names: Sequence[str] | None = None,
              name: str = "dae", phase_forcing: bool = False, vectorized: bool = False) -> dict:
    """Fields of ``periodyn.DAE(mass, force, constraint=None, ...)`` from per-point callables.
    mass: (n,n) array or callable ``mass(q)`` -> (n,n) (no parameters).
    force: ``force(q, qd, t, omega[, params])`` -> (n,).
    constraint: ``constraint(q, t, omega[, params])`` -> (m,), or None for an ODE.
    force_jacobian: ``(q, qd, t, omega[, params])`` -> (df/dq, df/dq'), each (n,n);
      default: complex-step differentiation of ``force`` (exact to round-off; the
      callable must accept complex q, qd).
    constraint_jacobian: ``(q, t, omega[, params])`` -> Phi_q (m,n); default: complex
      step of ``constraint`` (which must then accept complex q).
    constraint_hessian: ``(q, lam, t, omega[, params])`` -> sum_k lam_k Phi_k,qq (n,n);
      default: complex step of the given ``constraint_jacobian``, or central differences
      (relative step 1e-5, error ~1e-10) of the derived one.
    constraint_rates: ``(q, qd, t, omega[, params])`` -> (Phi_t (m,), gamma (m,)) with
      ``Phi_q q'' = gamma``; needed for integration/shooting. Default: a constraint
      without explicit time dependence, ``Phi_t = 0``, ``gamma_k = -qd^T Phi_k,qq qd``.
    mass_jacobian: ``(q, a)`` -> d(M(q) a)/dq (n,n); default complex step
      when ``mass`` is callable.
    parameters: named scalars passed as the last argument to every callable.
    q0: (n,) reference configuration (Newton's starting point).
    phase_forcing: True declares that the force depends on omega and t only through the
      phase omega t (e.g. ``F cos(omega t)``); the omega sensitivity of a shooting flow then
      needs no extra force evaluation (checked when used).
    vectorized: True declares that ``force`` (and ``force_jacobian``) take all samples at once,
      q, qd (p, n), t (p,) -> (p, n) (Jacobians (p, n, n) each): one call per evaluation.
    """
    params0 = dict(parameters) if parameters is not None else None
    extra = (lambda P: (P,)) if params0 is not None else (lambda P: ())

    if callable(mass):
        if n is None:
            if q0 is None:
                raise InputError("with a callable mass give n= or q0= so the number of coordinates is known")
            n = len(np.atleast_1d(q0))
    else:
        M = _finite_real("mass", mass, np.atleast_2d)
        if M.ndim != 2 or M.shape[0] != M.shape[1] or M.shape[0] == 0:
            raise InputError(f"mass must be a square (n,n) array (n >= 1) or a callable of q, got shape "
                             f"{np.shape(mass)}")
        n = M.shape[0]
    q0a = np.zeros(n) if q0 is None else _finite_real("q0", q0, np.atleast_1d)
    if q0a.shape != (n,):
        raise InputError(f"q0 must have the {n} coordinates of the mass matrix, got shape {q0a.shape}")
    if callable(mass):
        _finite_real("mass(q0)", mass(q0a), lambda a: a.reshape(n, n) if a.size == n * n else a)
    if not callable(force):
        raise InputError("force must be a callable force(q, qd, t, omega) returning an (n,) array")

    if vectorized:
        return _vectorized_fields(mass, force, constraint, n=n, force_jacobian=force_jacobian, parameters=params0,
                                  q0=q0a, coordinate_names=coordinate_names, constraint_names=constraint_names,
                                  name=name, phase_forcing=phase_forcing, constraint_jacobian=constraint_jacobian,
                                  constraint_hessian=constraint_hessian, constraint_rates=constraint_rates,
                                  mass_jacobian=mass_jacobian)

    def call_force(q, qd, t, w, P):
        return np.asarray(force(q, qd, t, w, *extra(P))).reshape(n)

    f_test = call_force(q0a, np.zeros(n), 0.0, 1.0, params0)
    if f_test.shape != (n,):
        raise InputError(f"force returned shape {f_test.shape}, expected ({n},)")

    # ---- mass
    if callable(mass):
        def mass_b(q):
            return np.stack([np.asarray(mass(qk), dtype=float).reshape(n, n) for qk in q])
        if mass_jacobian is not None:
            def mjac_b(q, a):
                return np.stack([np.asarray(mass_jacobian(qk, ak), dtype=float) for qk, ak in zip(q, a)])
        else:
            def mjac_b(q, a):
                return np.stack([complex_step(lambda x: np.asarray(mass(x)) @ ak, qk) for qk, ak in zip(q, a)])
    else:
        def mass_b(q):
            return np.broadcast_to(M, (q.shape[0], n, n))
        mjac_b = None

    # ---- force
    def force_b(q, qd, t, w, P):
        out = np.empty((q.shape[0], n))
        for k in range(q.shape[0]):
            out[k] = call_force(q[k], qd[k], float(t[k]), w, P)
        return out

    if force_jacobian is not None:
        def fjac_b(q, qd, t, w, P):
            Kq = np.empty((q.shape[0], n, n))
            Kv = np.empty((q.shape[0], n, n))
            for k in range(q.shape[0]):
                a, b = force_jacobian(q[k], qd[k], float(t[k]), w, *extra(P))
                Kq[k], Kv[k] = a, b
            return Kq, Kv
    else:
        def fjac_b(q, qd, t, w, P):
            Kq = np.stack([complex_step(lambda x: call_force(x, qd[k].astype(complex), float(t[k]), w, P), q[k])
                           for k in range(q.shape[0])])
            Kv = np.stack([complex_step(lambda v: call_force(q[k].astype(complex), v, float(t[k]), w, P), qd[k])
                           for k in range(q.shape[0])])
            return Kq, Kv
        _refuse_real_only(lambda: fjac_b(q0a[None], np.zeros((1, n)), np.zeros(1), 1.0, params0), "force",
                          "force_jacobian=(q, qd, t, omega) -> (df/dq, df/dqd)")

    # ---- constraint
    if constraint is None:
        m = 0

        def phi_b(q, t, w, P):
            return np.zeros((q.shape[0], 0))

        def phiq_b(q, t, w, P):
            return np.zeros((q.shape[0], 0, n))

        def hess_b(q, lam, t, w, P):
            return np.zeros((q.shape[0], n, n))

        def rates_b(q, qd, t, w, P):
            return np.zeros((q.shape[0], 0)), np.zeros((q.shape[0], 0))
    else:
        m = len(np.atleast_1d(constraint(q0a, 0.0, 1.0, *extra(params0))))
        derived = constraint_jacobian is None
        if derived:  # complex step of the constraint, like the force's
            def constraint_jacobian(q, t, w, *P):
                return complex_step(lambda x: constraint(x, t, w, *P), np.asarray(q, float)).reshape(m, n)
            _refuse_real_only(lambda: constraint_jacobian(q0a, 0.0, 1.0, *extra(params0)), "the constraint",
                              "constraint_jacobian=(q, t, omega) -> Phi_q (m, n)")

        def phi_b(q, t, w, P):
            return np.stack([np.asarray(constraint(q[k], float(t[k]), w, *extra(P)), dtype=float).reshape(m)
                             for k in range(q.shape[0])])

        def phiq_b(q, t, w, P):
            return np.stack([np.asarray(constraint_jacobian(q[k], float(t[k]), w, *extra(P)), dtype=float).reshape(m, n)
                             for k in range(q.shape[0])])

        def lam_phiq(q, lam, t, w, P):
            return np.asarray(constraint_jacobian(q, t, w, *extra(P))).T @ lam

        if constraint_hessian is not None:
            def hess_b(q, lam, t, w, P):
                return np.stack([np.asarray(constraint_hessian(q[k], lam[k], float(t[k]), w, *extra(P)), dtype=float)
                                 for k in range(q.shape[0])])
        elif not derived:  # complex step of the given Jacobian
            def hess_b(q, lam, t, w, P):
                return np.stack([complex_step(lambda x: lam_phiq(x, lam[k], float(t[k]), w, P), q[k])
                                 for k in range(q.shape[0])])
        else:  # central differences of the complex-step Jacobian (truncation ~1e-10 relative)
            def hess_b(q, lam, t, w, P):
                out = np.empty((q.shape[0], n, n))
                for k in range(q.shape[0]):
                    for j in range(n):
                        h = _FD_REL * max(1.0, abs(q[k, j]))
                        e = np.zeros(n)
                        e[j] = h
                        out[k, :, j] = (lam_phiq(q[k] + e, lam[k], float(t[k]), w, P)
                                        - lam_phiq(q[k] - e, lam[k], float(t[k]), w, P)) / (2 * h)
                return out

        if constraint_rates is not None:
            def rates_b(q, qd, t, w, P):
                pt = np.empty((q.shape[0], m))
                g = np.empty((q.shape[0], m))
                for k in range(q.shape[0]):
                    a, b = constraint_rates(q[k], qd[k], float(t[k]), w, *extra(P))
                    pt[k], g[k] = a, b
                return pt, g
        else:
            ph1 = phi_b(q0a[None], np.array([0.0]), 1.0, params0)
            ph2 = phi_b(q0a[None], np.array([0.731]), 1.0, params0)
            if not np.allclose(ph1, ph2, rtol=1e-14, atol=1e-14):
                raise InputError("the constraint depends explicitly on time, so pass constraint_rates=(q, qd, t, omega) -> "
                                 "(Phi_t, gamma) with Phi_q q'' = gamma for integration and shooting")

            def rates_b(q, qd, t, w, P):
                g = np.empty((q.shape[0], m))
                for i in range(m):
                    e = np.zeros((q.shape[0], m))
                    e[:, i] = 1.0
                    Hi = hess_b(q, e, t, w, P)
                    g[:, i] = -np.einsum("pi,pij,pj->p", qd, Hi, qd)
                return np.zeros((q.shape[0], m)), g

    names = tuple(coordinate_names) if coordinate_names is not None else tuple(f"q{i}" for i in range(n))
    cnames = tuple(constraint_names) if constraint_names is not None else tuple(f"lambda{i}" for i in range(m))
    return DAE.from_batch(n=n, m=m, mass=mass_b, force=force_b, force_jacobians=fjac_b, constraint=phi_b,
                          constraint_jacobian=phiq_b, constraint_hessian=hess_b, constraint_rates=rates_b,
                          mass_jacobian=mjac_b, q0=q0a, parameters=params0 or {}, coordinate_names=names,
                          constraint_names=cnames, name=name, phase_forcing=phase_forcing).__dict__


def ode(n: int, force, force_jacobians, coordinate_names, name: str):
    """``periodyn.DAE`` of the ODE q'' = force(q, qd, t, omega, params) (unit mass, m = 0)
    from batch callables ``force`` -> (p, n) and ``force_jacobians`` -> two (p, n, n)."""
    eye = np.eye(n)

    def empty(q, *rest):
        return np.zeros((q.shape[0], 0))

    return DAE.from_batch(
        n=n, m=0, mass=lambda q: np.broadcast_to(eye, (q.shape[0], n, n)), force=force,
        force_jacobians=force_jacobians, constraint=empty,
        constraint_jacobian=lambda q, *rest: np.zeros((q.shape[0], 0, n)),
        constraint_hessian=lambda q, lam, *rest: np.zeros((q.shape[0], n, n)),
        constraint_rates=lambda q, qd, *rest: (empty(q), empty(q)), coordinate_names=coordinate_names, name=name)


def rheo_linear_dae(system, *, name: str = "rheo_linear"):
    """ODE ``periodyn.DAE`` (n = system.n, m = 0, unit mass) of the rheo-linear system at
    its own omega; the omega passed to the solvers must be ``system.omega``. The result
    keeps the system as ``rheo_linear``."""
    S = system.inverse_mass_spectra
    stacked = StackedSpectra(S.damping, S.stiffness, S.force)

    def coefficients(t):
        return stacked.at(system.omega * np.asarray(t, float))

    def force(q, qd, t, omega, P):
        Pt, Qt, rt = coefficients(t)
        return rt - np.einsum("pij,pj->pi", Pt, qd) - np.einsum("pij,pj->pi", Qt, q)

    def force_jacobians(q, qd, t, omega, P):
        Pt, Qt, _ = coefficients(t)
        return -Qt, -Pt

    dae = ode(system.n, force, force_jacobians, system.coordinate_names, name)
    dae.rheo_linear = system  # for shooting(..., integrator="implicit")
    return dae


def _vectorized_fields(mass, force, constraint, *, n: int, force_jacobian, parameters, **rest) -> dict:
    """Fields of ``DAE(..., vectorized=True)``: mass, constraints as :func:`_user_fields`; force and
    Jacobians by one call over all samples (default: complex step, all 2n directions in one call)."""
    extra = (lambda P: (P,)) if parameters is not None else (lambda P: ())

    def one(q, qd, t, w, *P):
        return np.asarray(force(np.atleast_2d(q), np.atleast_2d(qd), np.atleast_1d(t), w, *P))[0]

    def jac_one(q, qd, t, w, *P):
        return tuple(a[0] for a in force_jacobian(np.atleast_2d(q), np.atleast_2d(qd), np.atleast_1d(t), w, *P))
    q0, z2 = rest["q0"], np.zeros((2, n))
    try:
        two = force(np.stack([q0, q0]), z2, np.array([0.0, 0.731]), 1.0, *extra(parameters))
        ok = np.shape(two) == (2, n) and np.allclose(two, [one(q0, z2[0], t, 1.0, *extra(parameters))
                                                          for t in (0.0, 0.731)], rtol=1e-12, atol=1e-14)
    except (IndexError, ValueError, TypeError):
        ok, two = False, None
    if not ok:
        raise InputError(f"force was declared vectorized but does not map q, qd (p, n), t (p,) to (p, n) per sample "
                         f"(2 samples gave {np.shape(two)}): use q[:, 0] for coordinate 0, or leave vectorized out")
    fields = _user_fields(mass, one, constraint, n=n, force_jacobian=force_jacobian and jac_one,
                          parameters=parameters, **rest)
    def force_b(q, qd, t, w, P):
        return np.asarray(force(q, qd, t, w, *extra(P)), dtype=float).reshape(q.shape[0], n)

    def fjac_b(q, qd, t, w, P):
        if force_jacobian is not None:
            return tuple(K if K.shape == (q.shape[0], n, n) else np.broadcast_to(K, (q.shape[0], n, n))
                         for K in (np.asarray(K, dtype=float) for K in force_jacobian(q, qd, t, w, *extra(P))))
        p = q.shape[0]  # row j of the stack: direction j (q for j < n, qd after) at every sample
        z = np.empty((2 * n, p, 2 * n), dtype=complex)
        z[:] = np.concatenate([q, qd], axis=1)
        z[np.arange(2 * n), :, np.arange(2 * n)] += 1j * _CSTEP
        z = z.reshape(2 * n * p, 2 * n)
        d = np.transpose(np.asarray(force(z[:, :n], z[:, n:], np.tile(t, 2 * n), w, *extra(P))).reshape(
            2 * n, p, n).imag / _CSTEP, (1, 2, 0))
        return d[:, :, :n], d[:, :, n:]
    return dict(fields, force=force_b, force_jacobians=fjac_b)
