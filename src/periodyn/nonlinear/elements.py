"""Element models (``periodyn.model.CompiledModel``) as non-linear problems: the full
reduced equations (4) of Schwab & Meijaard (2001) as a ``periodyn.DAE`` that shooting,
IHB, continuation and the integrators accept.

The inputs are rheonomic, ``q^r = g(omega t)`` (``rates * omega t`` at constant speed),
with the loads that vary with the driving angle, and are substituted, so the problem
is an ODE in the dynamic coordinates q^d alone (n = n_d, m = 0), periodic in t whenever
the rigid motion is, with unit mass and the force the dynamic accelerations

    q̈^d = g(q^d, q̇^d, t) = -M̄⁻¹ F_dᵀ (M F_qq q̇ q̇ - f)      (eq. 4 solved for q̈^d)

and its Jacobians ``-M̄⁻¹ K̄``, ``-M̄⁻¹ C̄`` at the actual accelerations (implicit
differentiation of eq. 4, :mod:`periodyn.kernels.mechanism.equations`). Keeping q^d as the only
coordinates (rather than adding q^r with a rheonomic constraint) keeps every coordinate
periodic, so harmonic balance, spectra and the periodic-solution type apply unchanged,
and needs no constraint stabilization in time integration.

Configurations x = F(q) are found by Newton from warm starts: the configurations solved
at the previous call for the same batch size (integrators and shooting move in small
steps), approached in steps of at most ``MAX_STEP`` in q when the new state is far. A
state whose configuration cannot be found (a trial step of an integrator far beyond the
mechanism's reach) gets NaN accelerations: step-size control rejects such a step, and
Newton solvers report the non-convergence (ConvergenceError).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..kernels.mechanism import assembly
from ..kernels.mechanism import equations as kernel
from ..kernels.mechanism.outputs import body_component, midpoint_deflection
from ..model.kinematics import MAX_HALVINGS, NEWTON_MAX_ITER, _tolerance
from ..dae import ode

__all__ = ["as_dae", "element_dae", "element_outputs", "reduced_equations"]

MAX_STEP = 0.25  # rad or m: largest change of q per tracked step between warm start and target


class _Configurations:
    """Solved configurations X (b, n_x) at inputs Qx (b, n_q) with their F_q (b, n_x, n_q),
    one set per batch size."""

    def __init__(self, model):
        self.model = model
        self.tol = _tolerance(model)
        self.sets: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    def start(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Warm starts (X, Qx, FQ) for Q (b, n_q): configurations within MAX_STEP of Q."""
        b = Q.shape[0]
        if b in self.sets:  # updated in place by the kernel, row by row
            X, Qx, FQ = self.sets[b]
        elif self.sets:  # another batch size: start every row from the latest first row
            X, Qx, FQ = (np.repeat(a[:1], b, axis=0) for a in self.sets[next(reversed(self.sets))])
        else:
            X = np.repeat(self.model.x_reference[None], b, axis=0)
            Qx = np.zeros_like(Q)
            FQ = np.repeat(assembly.input_jacobian(self.model.arrays, self.model.x_reference)[None], b, axis=0)
        for k in np.nonzero(np.abs(Q - Qx).max(axis=1) > MAX_STEP)[0]:
            steps = int(np.ceil(np.abs(Q[k] - Qx[k]).max() / MAX_STEP))
            path = Qx[k] + np.outer(np.arange(1, steps) / steps, Q[k] - Qx[k])
            if len(path):
                out, info = np.empty((len(path), X.shape[1])), np.zeros((len(path), 2))
                failed = assembly.track(self.model.arrays, X[k].copy(), Qx[k].copy(), path, self.tol,
                                        NEWTON_MAX_ITER, MAX_HALVINGS, out, info)
                last = len(path) - 1 if failed < 0 else failed - 1  # the kernel reports a failure itself
                if last < 0:
                    continue
                X[k], Qx[k] = out[last], path[last]
                FQ[k] = assembly.input_jacobian(self.model.arrays, X[k])
        return X, Qx, FQ

    def keep(self, X: np.ndarray, Qx: np.ndarray, FQ: np.ndarray) -> None:
        self.sets.pop(X.shape[0], None)
        self.sets[X.shape[0]] = (X, Qx, FQ)


class ElementEquations:
    """Batch evaluator of the accelerations of an element model (module docstring);
    remembers the last Jacobian evaluation, so repeated Jacobians at one state cost one pass."""

    def __init__(self, model):
        if model.independent:
            raise InputError(f"model '{model.name}' has independently modelled elements (eq. 11-12); they exist "
                             "only in the linearized equations, so the non-linear model cannot include them")
        if model.n_dynamic == 0:
            raise InputError(f"model '{model.name}' has no dynamic coordinates: nothing to integrate")
        self.model = model
        self.configurations = _Configurations(model)
        self._last = None
        self._none = np.empty((1, 1, 1))
        self.rates, self.n_inputs = np.asarray(model.input_rates, float), model.n_inputs

    def inputs(self, q, qd, t, omega) -> tuple[np.ndarray, np.ndarray]:
        """Full q and q̇ (b, n_q) of dynamic states q, qd (b, n_d) at times t (b,)."""
        b, nr = q.shape[0], self.n_inputs
        Q = np.empty((b, nr + q.shape[1]))
        Qd = np.empty_like(Q)
        if self.model.input_motions:
            g, dg, _ = self.model.drive(omega * np.asarray(t, float).reshape(b))
            Q[:, :nr], Qd[:, :nr] = g, omega * dg
        else:
            Q[:, :nr] = np.multiply.outer(omega * np.asarray(t, float), self.rates).reshape(b, nr)
            Qd[:, :nr] = omega * self.rates
        Q[:, nr:] = q
        Qd[:, nr:] = qd
        return Q, Qd

    def driving(self, t, omega) -> tuple[np.ndarray, np.ndarray]:
        """Prescribed accelerations (b, n_q) (zero dynamic part) and the loads that vary
        with the driving angle (b, n_x) at times t (b,)."""
        t = np.asarray(t, float).reshape(-1)
        Qdd = np.zeros((t.size, self.n_inputs + self.model.n_dynamic))
        if self.model.uniform:
            return Qdd, np.zeros((t.size, self.model.n_coordinates))
        Qdd[:, :self.n_inputs] = omega**2 * self.model.drive(omega * t)[2]
        return Qdd, self.model.applied_loads(omega * t)

    def __call__(self, q, qd, t, omega, jacobians: bool):
        """(acc (b, n_d), Gq, Gv (b, n_d, n_d) or None) at states q, qd (b, n_d), times t."""
        q = np.ascontiguousarray(q, dtype=float)
        qd = np.ascontiguousarray(qd, dtype=float)
        last = self._last
        if (jacobians and last is not None and last[0] and last[1] == float(omega) and np.array_equal(last[2], q)
                and np.array_equal(last[3], qd) and np.array_equal(last[4], t)):
            return last[5:]
        Q, Qd = self.inputs(q, qd, t, omega)
        X, Qx, FQ = self.configurations.start(Q)
        b, nd = q.shape
        acc = np.empty((b, nd))
        Gq, Gv = (np.empty((b, nd, nd)), np.empty((b, nd, nd))) if jacobians else (self._none, self._none)
        info = np.zeros((b, 2))
        kernel.accelerations(self.model.arrays, Q, Qd, *self.driving(t, omega), X, Qx, FQ, self.configurations.tol,
                             NEWTON_MAX_ITER, MAX_HALVINGS, jacobians, acc, Gq, Gv, info)
        failed = info[:, 0] < 0
        if failed.any():  # rejected by a step-size control, reported by a Newton solver
            acc[failed] = np.nan
            if jacobians:
                Gq[failed] = Gv[failed] = np.nan
        self.configurations.keep(X, Qx, FQ)
        if not jacobians:
            return acc, None, None
        self._last = (True, float(omega), q.copy(), qd.copy(), np.array(t, float), acc, Gq, Gv)
        return acc, Gq, Gv


def element_dae(model, *, name: str | None = None):
    """``periodyn.DAE`` (an ODE in q^d, n = n_d, m = 0) of the full non-linear equations
    of the element model ``model`` (module docstring); coordinates named as
    ``model.dynamic_names``. Refuses models with independent elements or without
    dynamic coordinates (InputError)."""
    eq = ElementEquations(model)

    def force(q, qd, t, omega, P):
        return eq(q, qd, t, omega, False)[0].copy()

    def force_jacobians(q, qd, t, omega, P):
        _, Gq, Gv = eq(q, qd, t, omega, True)
        return Gq.copy(), Gv.copy()

    system = ode(model.n_dynamic, force, force_jacobians, model.dynamic_names, name or f"{model.name}_nonlinear")
    system.equations = eq
    return system


def as_dae(system, caller: str):
    """The problem ``shooting``, ``ihb`` and ``continuation`` (``caller``) solve: a
    ``periodyn.DAE`` as it is, an element model (``periodyn.model.Model``, compiled here,
    or ``CompiledModel``) as its full non-linear equations :func:`element_dae`. Anything
    else is refused (InputError naming what to pass)."""
    from ..dae import DAE
    from ..model import CompiledModel, Model

    if isinstance(system, DAE):
        return system
    if isinstance(system, Model):
        system = system.compile()
    if isinstance(system, CompiledModel):
        return element_dae(system)
    raise InputError(f"{caller} expects a periodyn.DAE or an element model (periodyn.model.Model or CompiledModel), "
                     f"got {type(system).__name__}: for a linearized model (RheoLinear) use periodyn.rheo_linear_dae, "
                     "for an OmegaSplitModel give the element model it was built from")


def reduced_equations(model, omega: float, t, q, qd, qdd):
    """The reduced equations (4) in residual form at states q, qd, qdd (k, n_d) (rad, m,
    per s, per s^2) at times t (k,) (s), input speed omega (rad/s): residual
    R = F_dᵀ (M x'' - f) (k, n_d) and its derivatives M̄ = dR/dq̈, C̄ = dR/dq̇, K̄ = dR/dq
    (k, n_d, n_d). At q = qd = qdd = 0 these are the linearized matrices of eq. (5, 7, 9, 10)."""
    q, qd, qdd = (np.atleast_2d(np.asarray(a, dtype=float)) for a in (q, qd, qdd))
    t = np.asarray(t, dtype=float).reshape(-1)
    eq = ElementEquations(model)
    k, nd = q.shape
    R, Mb, Cb, Kb = np.empty((k, nd)), np.empty((k, nd, nd)), np.empty((k, nd, nd)), np.empty((k, nd, nd))
    for j in range(k):
        eq(q[j:j + 1], qd[j:j + 1], t[j:j + 1], omega, False)
        Q, Qd = eq.inputs(q[j:j + 1], qd[j:j + 1], t[j:j + 1], omega)
        Qdd, loads = eq.driving(t[j:j + 1], omega)
        qddot = np.concatenate([Qdd[0, :model.n_inputs], qdd[j]])
        kernel._state(model.arrays, eq.configurations.sets[1][0][0], Qd[0], qddot, loads[0], Mb[j], Cb[j], Kb[j], R[j])
    return R, Mb, Cb, Kb


def _values(model, X: np.ndarray) -> np.ndarray:
    """Output functionals y(x) (k, n_out) at configurations X (k, n_x)."""
    y = np.empty((X.shape[0], len(model.outputs)))
    grad = np.empty(10)
    tensors = assembly.allocate_tensors(model.arrays)
    for j, x in enumerate(X):
        if any(o.kind == "mode" for o in model.outputs):
            assembly.element_tensors(model.arrays, x, *tensors)
        for i, o in enumerate(model.outputs):
            xs = x[o.dofs]
            if o.kind == "midpoint_deflection":
                y[j, i] = midpoint_deflection(np.ascontiguousarray(xs), o.scale, grad)
            elif o.kind == "coordinate":
                y[j, i] = xs[0] / o.scale
            elif o.kind == "relative_rotation":
                y[j, i] = xs[1] - xs[0]
            elif o.kind == "body_component":
                y[j, i] = body_component(np.ascontiguousarray(xs), o.direction, o.scale, grad)
            else:
                y[j, i] = tensors[0][o.element, o.mode] / o.scale
    return y


def element_outputs(model, omega: float, t, q) -> np.ndarray:
    """Non-linear outputs of ``model`` along a motion: q^d (k, n_d) at times t (k,) (s),
    input speed omega (rad/s) -> (k, n_out), each output minus its value on the rigid
    motion (q^d = 0) at the same time, comparable with the linearized outputs."""
    q = np.atleast_2d(np.asarray(q, dtype=float))
    t = np.asarray(t, dtype=float).reshape(-1)
    if q.shape != (t.size, model.n_dynamic):
        raise InputError(f"q must have shape ({t.size}, {model.n_dynamic}) for {t.size} times, got {q.shape}")
    eq = ElementEquations(model)
    rows = []
    for qs in (q, np.zeros_like(q)):
        X = np.empty((t.size, model.n_coordinates))
        for k in range(t.size):  # one state at a time: each starts from the previous one
            eq(qs[k:k + 1], np.zeros((1, model.n_dynamic)), t[k:k + 1], omega, False)
            X[k] = eq.configurations.sets[1][0][0]
        rows.append(_values(model, X))
    return rows[0] - rows[1]
