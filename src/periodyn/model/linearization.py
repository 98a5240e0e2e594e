"""Linearized equations about the nominal rigid motion (Schwab & Meijaard 2001,
section 2.2-2.3): additional forces f^d (eq. 7), reduced M, C, K (eq. 5, 9, 10) at
every sample angle, independently modelled elements (eq. 11-12), output maps, and the
split into omega-polynomials for inputs that are functions of the driving angle,
q^r = g(theta) with theta = omega t (``rates * theta`` at constant speed).

Sign convention of the result (as :class:`periodyn.RheoLinear`):
``M q'' + C q' + K q = f`` with ``f = -f^d + f_a`` (eq. 8, 13).

With such inputs, q^r' = omega g'(theta) and q^r'' = omega^2 g''(theta): velocities
scale with omega and accelerations with omega^2 (eq. 7's F_{,q^r} q^r'' term included),
and loads that are functions of theta carry no power of omega, so C = C0 + w C1,
K = K0 + w K1 + w^2 K2, f = f0 + w f1 + w^2 f2 exactly; the split
is computed once per sample (:mod:`.kernels.split`), and checked against direct
linearization in the tests.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..kernels.mechanism import assembly, constraint_system, split
from ..numerics.spectra import sample_angles
from .kinematics import configuration, motion, nominal_configurations
from ..system import OmegaSplitModel, RheoLinear

__all__ = ["LinearizedSamples", "independent_terms", "linearize", "rheo_linear", "omega_split", "output_maps", "reduced_residual"]


@dataclass(frozen=True)
class LinearizedSamples:
    """Linearized equations at one input speed omega (rad/s) and p crank angles
    theta_j = 2 pi j / p: mass, damping, stiffness (p, n_d, n_d), additional_force f^d
    of eq. (7) (p, n_d), applied_force f_a of eq. (12) (p, n_d), configurations
    (p, n_x), transfer_jacobian F_q^d (p, n_x, n_d)."""

    omega: float
    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    additional_force: np.ndarray
    applied_force: np.ndarray
    configurations: np.ndarray
    transfer_jacobian: np.ndarray

    @property
    def force(self) -> np.ndarray:
        """Right-hand side of eq. (13): ``-f^d + f_a``, (p, n_d)."""
        return -self.additional_force + self.applied_force


def _unit_rates(model, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Input rates and accelerations at unit speed, (k, n_q) (zero dynamic part), and the
    loads that vary with theta (k, n_x), at angles theta (k,)."""
    nr = model.n_inputs
    qdot1, qddot1 = np.zeros((2, theta.size, nr + model.n_dynamic))
    _, qdot1[:, :nr], qddot1[:, :nr] = model.drive(theta)
    return qdot1, qddot1, model.applied_loads(theta)


def _run(model, X: np.ndarray, speeds) -> tuple[np.ndarray, ...]:
    """reduced_sample at every configuration X (p, n_x), at theta_j = 2 pi j / p, for
    every input speed s (rad/s)."""
    arr = model.arrays
    p, n = X.shape
    nd = model.n_dynamic
    S = len(speeds)
    qdot1, qddot1, loads = _unit_rates(model, sample_angles(p))
    speeds = np.asarray(speeds, dtype=float)
    qdots = speeds[:, None, None] * qdot1[None]
    qddots = speeds[:, None, None]**2 * qddot1[None]
    out = (np.empty((S, p, nd, nd)), np.empty((S, p, nd, nd)), np.empty((S, p, nd, nd)), np.empty((S, p, nd)),
           np.empty((S, p, n, nd)), np.empty((S, p, n, nd)), np.empty((S, p, n, nd)))
    for j in range(p):  # Python loops: a jitted one would have Numba compile reduced_sample's body again
        for k in range(S):
            assembly.reduced_sample(arr, X[j], qdots[k, j], qddots[k, j], loads[j], *(o[k, j] for o in out))
    return out


def _element_coefficients(el, k: int):
    """Mass (k,k), damping and stiffness lists over omega powers, force (k,) of an
    independent element, validated so the equations stay quadratic in omega."""
    if len(el.damping) > 2 or len(el.stiffness) > 3:
        raise InputError(f"independent element '{el.name}': give stiffness up to omega^2 and damping up to "
                         "omega^1 only, so the linearized equations stay quadratic in omega")
    mass = np.zeros((k, k)) if el.mass is None else np.asarray(el.mass, dtype=float).reshape(k, k)
    force = np.zeros(k) if el.force is None else np.asarray(el.force, dtype=float).reshape(k)
    return (mass, [np.asarray(c, dtype=float).reshape(k, k) for c in el.damping],
            [np.asarray(c, dtype=float).reshape(k, k) for c in el.stiffness], force)


def independent_terms(independent, Fd, Fdv, Fda):
    """Eq. (11-12) for independent elements [(element, coordinate indices)], as
    polynomials in omega.

    Fd (p, n_x, n_d) = F_q^d; Fdv, Fda at unit input speed (they scale with omega,
    omega^2). Returns mass (p,nd,nd), damping [w^0, w^1], stiffness [w^0, w^1, w^2]
    (each (p,nd,nd)) and force (p,nd)."""
    p, _, nd = Fd.shape
    M = np.zeros((p, nd, nd))
    C = [np.zeros((p, nd, nd)) for _ in range(2)]
    K = [np.zeros((p, nd, nd)) for _ in range(3)]
    f = np.zeros((p, nd))
    for el, idx in independent:
        Me, Ce, Ke, fe = _element_coefficients(el, len(idx))
        A, Av, Aa = Fd[:, idx], Fdv[:, idx], Fda[:, idx]   # (p, k, nd)
        At = np.swapaxes(A, 1, 2)
        M += At @ Me @ A
        f += np.einsum("pki,k->pi", A, fe)
        C[1] += 2.0 * At @ Me @ Av
        K[2] += At @ Me @ Aa
        for power, Cp in enumerate(Ce):
            C[power] += At @ Cp @ A
            K[power + 1] += At @ Cp @ Av
        for power, Kp in enumerate(Ke):
            K[power] += At @ Kp @ A
    return M, C, K, f


def _add_independent(model, Fd, Fdv, Fda, omega):
    """:func:`independent_terms` of the model's independent elements; if omega is
    given, the powers are summed."""
    M, C, K, f = independent_terms(model.independent, Fd, Fdv, Fda)
    if omega is None:
        return M, C, K, f
    return M, C[0] + omega * C[1], K[0] + omega * K[1] + omega**2 * K[2], f


def linearize(model, omega: float, samples: int) -> LinearizedSamples:
    """Direct linearization at input speed omega (rad/s) over ``samples`` crank angles."""
    omega = float(omega)
    X = nominal_configurations(model, samples)
    Mb, Cb, Kb, fd, Fd, Fdv, Fda = (a[0] for a in _run(model, X, [omega]))
    scale_v = 1.0 / omega if omega != 0.0 else 0.0
    Mi, Ci, Ki, fi = _add_independent(model, Fd, Fdv * scale_v, Fda * scale_v**2, omega)
    return LinearizedSamples(omega, Mb + Mi, Cb + Ci, Kb + Ki, fd, fi, X, Fd)


def rheo_linear(model, omega: float, samples: int) -> RheoLinear:
    """The rheo-linear system (eq. 13) at input speed omega (rad/s), with output maps."""
    lin = linearize(model, omega, samples)
    G = output_maps(model, lin.configurations, lin.transfer_jacobian)
    return RheoLinear.from_samples(lin.mass, lin.damping, lin.stiffness, lin.force, omega,
                                   coordinate_names=model.dynamic_names, output_maps=G if G.shape[1] else None,
                                   output_names=model.output_names if G.shape[1] else None)


def _split(model, X: np.ndarray, theta: np.ndarray, speed: float) -> tuple[np.ndarray, ...]:
    """:func:`kernels.split.split_sample` at each of the configurations X (p, n_x) at angles theta (p,): M (p,nd,nd),
    C [w^0, w^1], K [w^0, w^1, w^2] (each (p,nd,nd)), f^d [w^0, w^1, w^2] (each (p,nd)),
    and F_q^d, F_{q^d q} q', F_{q^d q q} q' q' at unit speed (p, n_x, nd)."""
    X = np.ascontiguousarray(X)
    p, n = X.shape
    nd = model.n_dynamic
    qdot1, qddot1, loads = _unit_rates(model, theta)
    M, C, K, fd = np.empty((p, nd, nd)), np.empty((p, 2, nd, nd)), np.empty((p, 3, nd, nd)), np.empty((p, 3, nd))
    F = tuple(np.empty((p, n, nd)) for _ in range(3))
    Fd, Fdv, Fda = F
    for j in range(p):  # a Python loop: a jitted one would have Numba compile split_sample's body again
        split.split_sample(model.arrays, X[j], qdot1[j], qddot1[j], loads[j], float(speed), M[j], C[j], K[j], fd[j],
                           Fd[j], Fdv[j], Fda[j])
    return (M, list(np.moveaxis(C, 1, 0)), list(np.moveaxis(K, 1, 0)), list(np.moveaxis(fd, 1, 0))) + F


def omega_split(model, samples: int, *, name: str | None = None, rebuild=None, metadata=None) -> OmegaSplitModel:
    """Linearized equations as omega-polynomials, sampled at ``samples`` crank angles;
    kinematics solved and the transfer function differentiated once per sample. ``rebuild(p)``
    and ``metadata`` are passed on to the OmegaSplitModel.

    The element arrays are split into powers from input speeds -S, 0, +S
    (:mod:`.kernels.split`), with S the speed at which the omega^2 terms of the reduced
    stiffness match the omega^0 terms (found from a first pass at S = 1 rad/s on at most
    8 samples), which keeps the rounding error of the split at machine precision relative
    to the matrices at operating speeds."""
    X, theta = nominal_configurations(model, samples), sample_angles(samples)
    step = max(1, samples // 8)
    K2 = _split(model, X[::step], theta[::step], 1.0)[2]
    big, small = np.abs(K2[0]).max(), np.abs(K2[2]).max()
    speed = float(np.clip(np.sqrt(big / small), 1e-3, 1e6)) if small > 0 and big > 0 else 1.0
    Mb, Cb, Kb, fd, Fd, Fdv, Fda = _split(model, X, theta, speed)
    Mi, Ci, Ki, fi = _add_independent(model, Fd, Fdv, Fda, None)
    C = [c + ci for c, ci in zip(Cb, Ci)]
    K = [k + ki for k, ki in zip(Kb, Ki)]
    f = [-c for c in fd]
    f[0] = f[0] + fi
    G = output_maps(model, X, Fd)
    has_out = G.shape[1] > 0
    return OmegaSplitModel.from_samples(
        Mb + Mi, C, K, f, coordinate_names=model.dynamic_names,
        output_maps=G if has_out else None, output_names=model.output_names if has_out else None,
        name=name or model.name, rebuild=rebuild, metadata=metadata)


def output_maps(model, X: np.ndarray, Fd: np.ndarray | None = None) -> np.ndarray:
    """Linear output maps G_j = y_x F_q^d at the configurations X (p, n_x), with
    F_q^d (p, n_x, n_d) if already known; (p, n_out, n_d)."""
    p = X.shape[0]
    n_out = len(model.outputs)
    G = np.zeros((p, n_out, model.n_dynamic))
    if n_out == 0:
        return G
    qdot = np.zeros(model.n_inputs + model.n_dynamic)
    tensors = constraint_system.allocate_tensors(model.arrays) if any(o.kind == "mode" for o in model.outputs) else None
    for j in range(p):
        Fd_j = motion(model, X[j], qdot, qdot).Fd if Fd is None else Fd[j]
        if tensors is not None:
            constraint_system.element_tensors(model.arrays, X[j], *tensors)
        for o, out in enumerate(model.outputs):
            G[j, o] = out.gradient(X[j], None if tensors is None else tensors[1]) @ Fd_j[out.dofs]
    return G


def reduced_residual(model, theta: float, qd, qd_dot, qd_ddot, omega: float) -> np.ndarray:
    """Residual of the non-linear reduced equations (4), ``F_d^T (M x'' - f)`` (n_d,),
    at crank angle theta (rad), dynamic coordinates and rates (n_d,) and input speed
    omega (rad/s); zero on a solution, equal to f^d at the nominal state."""
    x = configuration(model, theta, qd)
    nr = model.n_inputs
    qdot1, qddot1, loads = _unit_rates(model, np.array([float(theta)]))
    qdot = np.concatenate([omega * qdot1[0, :nr], np.asarray(qd_dot, dtype=float)])
    qddot = np.concatenate([omega**2 * qddot1[0, :nr], np.asarray(qd_ddot, dtype=float)])
    nd, n = model.n_dynamic, model.n_coordinates
    Mb, Cb, Kb = (np.empty((nd, nd)) for _ in range(3))
    fd = np.empty(nd)
    Fd, Fdv, Fda = (np.empty((n, nd)) for _ in range(3))
    assembly.reduced_sample(model.arrays, x, qdot, qddot, loads[0], Mb, Cb, Kb, fd, Fd, Fdv, Fda)
    return fd
