"""Stiff time integration of ODE models (``periodyn.DAE`` with m = 0), such as element
models with flexible members (element eigenfrequencies far above the driving frequency):
an implicit method with error control (scipy Radau or BDF through the one integrator
wrapper ``integrate.solve``) and the analytic Jacobian

    d/dy [q', q''] = [[0, I], [M⁻¹ (f_q - d(M a)/dq), M⁻¹ f_q']],   a = M⁻¹ f,

from the model's force Jacobians (and mass Jacobian when the mass depends on q).
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError
from .integration import TimeHistory, solve
from .options import IntegrationOptions, merge_options

__all__ = ["STIFF_DEFAULTS", "integrate_stiff"]


#: the defaults of integrate_stiff
STIFF_DEFAULTS = IntegrationOptions(integrator="Radau", rtol=1e-8, atol=1e-10)


def integrate_stiff(system, omega: float, t_span, q0, qd0, *, t_eval=None, params=None,
                    options: IntegrationOptions | None = None, **keywords) -> TimeHistory:
    """Integrate an ODE model from (q0, qd0) (n,) over t_span (s) at driving frequency
    omega (rad/s) with an implicit method and the analytic Jacobian; returns a
    TimeHistory at t_eval (default the solver's steps), lam of width 0.

    options: an :class:`IntegrationOptions` (default ``STIFF_DEFAULTS``: Radau, rtol 1e-8,
    atol 1e-10); keywords integrator ("Radau" or "BDF"), rtol, atol and max_step override its
    fields (``method=``, the deprecated spelling of integrator, warns)."""
    if "method" in keywords:
        method = keywords.pop("method")
        warnings.warn("integrate_stiff(method=...) is deprecated and goes in the next release; pass "
                      f"integrator={method!r}", DeprecationWarning, stacklevel=2)
        keywords.setdefault("integrator", method)
    opts = merge_options(IntegrationOptions, STIFF_DEFAULTS if options is None else options, keywords,
                         "integrate_stiff")
    if system.m:
        raise InputError("integrate_stiff integrates ODE models (no constraints); use "
                         "periodyn.numerics.integration for a constrained DAE")
    if opts.integrator not in ("Radau", "BDF"):
        raise InputError(f"integrate_stiff's integrator must be 'Radau' or 'BDF' (implicit, with the analytic "
                         f"Jacobian), got {opts.integrator!r}")
    n = system.n
    P = system.parameters if params is None else params
    q0 = np.asarray(q0, float).reshape(n)
    qd0 = np.asarray(qd0, float).reshape(n)

    def split(t, y):
        return y[None, :n], y[None, n:], np.array([t])

    def rhs(t, y):
        q, qd, T = split(t, y)
        a = np.linalg.solve(system.mass(q)[0], system.force(q, qd, T, omega, P)[0])
        return np.concatenate([y[n:], a])

    def jac(t, y):
        q, qd, T = split(t, y)
        M = system.mass(q)[0]
        fq, fv = (J[0] for J in system.force_jacobians(q, qd, T, omega, P))
        if system.mass_jacobian is not None:
            a = np.linalg.solve(M, system.force(q, qd, T, omega, P)[0])
            fq = fq - system.mass_jacobian(q, a[None])[0]
        J = np.zeros((2 * n, 2 * n))
        J[:n, n:] = np.eye(n)
        J[n:, :n] = np.linalg.solve(M, fq)
        J[n:, n:] = np.linalg.solve(M, fv)
        return J

    sol = solve(rhs, t_span, np.concatenate([q0, qd0]), t_eval=t_eval, rtol=opts.rtol, atol=opts.atol,
                method=opts.integrator, max_step=opts.max_step, jac=jac)
    return TimeHistory(sol.t, sol.y[:n].T, sol.y[n:].T, np.zeros((len(sol.t), 0)), int(sol.nfev))
