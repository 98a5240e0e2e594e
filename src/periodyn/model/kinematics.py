"""Kinematics: the transfer function ``x = F(q)`` by Newton iteration on the constraint
equations, and its derivatives by implicit differentiation (Schwab & Meijaard 2001,
section 2.1, eq. 1 and 3).

Works at any crank angle theta and any dynamic coordinates q^d (the full non-linear
model reuses it). Configurations are followed by continuation from the reference
configuration, so a mechanism stays on its assembly branch.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError, InputError
from ..kernels.mechanism import constraint_system, lu, split, transfer
from ..numerics.spectra import sample_angles

__all__ = ["Motion", "check_constraints", "check_inertia", "nominal_configurations", "configuration", "motion"]

NEWTON_TOL = 1e-12   # inf-norm of the constraint residual, relative to the model size
NEWTON_MAX_ITER = 25
MAX_HALVINGS = 12


def _tolerance(model) -> float:
    return NEWTON_TOL * max(1.0, float(np.max(np.abs(model.x_reference))))


def check_constraints(model) -> None:
    """Raise InputError naming the coordinates/equations if the constraint Jacobian is
    singular in the reference configuration (a mechanism that is under-constrained in
    some coordinates and over-constrained in some equations).

    The test is the SVD's ``s_min <= 1e-10 s_max``; a Jacobian whose LU factors give a
    1-norm condition estimate below ``1e10 / (10 n)`` passes without the SVD (the 2-norm
    condition is at most n times the 1-norm one, and the estimate is rarely off by more
    than a small factor), so only nearly singular Jacobians pay its n^3 cost."""
    D, Dx, Dxx, Dxxx, Phi, J = constraint_system.allocate_equations(model.arrays)
    constraint_system.equations(model.arrays, model.x_reference, model.arrays.rhs0, D, Dx, Dxx, Dxxx, Phi, J)
    LU, piv = J.copy(), np.empty(J.shape[0], dtype=np.int64)
    if lu.lu_factor(LU, piv) == 0 and lu.norm1(J) * lu.inverse_norm1(LU, piv) * 10 * J.shape[0] < 1e10:
        return
    U, s, Vt = np.linalg.svd(J)
    if s[-1] > 1e-10 * s[0]:
        return
    free = [model.coordinate_names[i] for i in np.nonzero(np.abs(Vt[-1]) > 1e-6)[0]]
    redundant = [model.constraint_labels[i] for i in np.nonzero(np.abs(U[:, -1]) > 1e-6)[0]]
    raise InputError(
        f"model '{model.name}': the constraints do not determine the configuration. "
        f"Coordinates {free} can move without changing any constrained quantity (under-constrained), "
        f"while the equations {redundant} are redundant (over-constrained). "
        "Make one of the redundant modes free, or constrain the moving coordinates")


def check_inertia(model) -> None:
    """Raise InputError naming the dynamic coordinates if the reduced mass matrix
    ``F_d^T M F_d`` is singular in the reference configuration (a dynamic coordinate or
    flexible mode that moves no mass)."""
    nd, n = model.n_dynamic, model.n_coordinates
    if nd == 0:
        return
    zeros = np.zeros(model.n_inputs + nd)
    Mb = np.empty((nd, nd))
    # the omega-split kernel, which the model's linearization loads anyway (reduced_sample would be one more to load)
    split.split_sample(model.arrays, model.x_reference, zeros, zeros, np.zeros(n), 1.0, Mb, np.empty((2, nd, nd)),
                       np.empty((3, nd, nd)), np.empty((3, nd)), *(np.empty((n, nd)) for _ in range(3)))
    w, V = np.linalg.eigh(0.5 * (Mb + Mb.T))
    if w[0] > 1e-12 * max(abs(w[-1]), 1e-300):
        return
    massless = [model.dynamic_names[i] for i in np.nonzero(np.abs(V[:, 0]) > 1e-6)[0]]
    raise InputError(
        f"model '{model.name}': singular mass matrix, the dynamic coordinates {massless} move no mass. "
        "Add a point mass (add_mass), a rotational inertia (add_inertia / add_rigid_body) or element mass "
        "(mass_per_length) that they move, or make them rigid/fixed instead of dynamic")


def _raise_failure(model, info_row, what: str):
    kind = "singular constraint Jacobian (a dead point or a branch point)" if info_row[0] == -1 \
        else "no convergence"
    raise ConvergenceError(
        f"model '{model.name}': Newton iteration on the constraints failed at {what} ({kind}, residual "
        f"{info_row[1]:.3g} after step halving). Check the geometry (can the mechanism reach this position?) "
        "or use more samples so the continuation steps are smaller", residual=float(info_row[1]))


def _track(model, q_targets: np.ndarray, labels, x0=None, q0=None) -> np.ndarray:
    """Follow the configuration through q_targets (p, n_q) from (x0, q0), by default
    the reference configuration."""
    arr = model.arrays
    p = q_targets.shape[0]
    X = np.empty((p, model.n_coordinates))
    info = np.zeros((p, 2))
    x0 = model.x_reference.copy() if x0 is None else np.array(x0, dtype=float)
    q0 = np.zeros(model.n_inputs + model.n_dynamic) if q0 is None else np.asarray(q0, dtype=float)
    failed = transfer.track(arr, x0, q0, np.ascontiguousarray(q_targets, dtype=float),
                            _tolerance(model), NEWTON_MAX_ITER, MAX_HALVINGS, X, info)
    if failed >= 0:
        _raise_failure(model, info[failed], labels(failed))
    return X


def nominal_configurations(model, samples: int) -> np.ndarray:
    """Nodal coordinates of the nominal rigid motion (q^d = 0) at the crank angles
    theta_j = 2 pi j / p; (p, n_x)."""
    theta = sample_angles(samples)
    q = np.zeros((samples, model.n_inputs + model.n_dynamic))
    q[:, :model.n_inputs] = model.drive(theta)[0]
    return _track(model, q, lambda j: f"crank angle theta = {theta[j]:.6g} rad (sample {j})")


def _dynamic(model, qd) -> np.ndarray:
    qd = np.zeros(model.n_dynamic) if qd is None else np.asarray(qd, dtype=float)
    if qd.shape != (model.n_dynamic,):
        raise InputError(f"qd must have shape ({model.n_dynamic},) for the dynamic coordinates "
                         f"{list(model.dynamic_names)}, got {qd.shape}")
    return qd


def configuration(model, theta: float, qd=None, steps: int | None = None, *, start=None) -> np.ndarray:
    """Nodal coordinates x = F(q) (n_x,) at crank angle theta (rad) and dynamic
    coordinates qd (n_d,), continued in ``steps`` straight steps in q from the reference
    configuration (default 8 steps) or, warm-started, from ``start = (x, theta, qd)``, a
    solved configuration near the target (default 1 step; Newton halves steps that fail)."""
    qd = _dynamic(model, qd)
    target = np.concatenate([model.inputs(theta), qd])
    if start is None:
        x0, q0, steps = None, np.zeros_like(target), steps or 8
    else:
        x0, theta0, qd0 = start
        x0 = np.asarray(x0, dtype=float)
        if x0.shape != (model.n_coordinates,):
            raise InputError(f"start: x must have shape ({model.n_coordinates},), got {x0.shape}")
        q0, steps = np.concatenate([model.inputs(theta0), _dynamic(model, qd0)]), steps or 1
    path = q0 + np.outer(np.arange(1, steps + 1) / steps, target - q0)
    return _track(model, path, lambda j: f"theta = {theta:.6g} rad, q^d = {qd.tolist()}", x0, q0)[-1]


@dataclass(frozen=True)
class Motion:
    """Transfer-function derivatives at one configuration: x, v = x', a = x'' (n_x,)
    (m, m/s, m/s^2 or rad...), Fd = F_q^d (n_x, n_d), Fdv = F_{q^d q} q' (n_x, n_d) (1/s),
    Fdd = F_{q^d q^d} (n_x, n_d, n_d), Fda = F_{q^d q} q'' + F_{q^d q q} q' q' (1/s^2)."""

    x: np.ndarray
    v: np.ndarray
    a: np.ndarray
    Fd: np.ndarray
    Fdv: np.ndarray
    Fdd: np.ndarray
    Fda: np.ndarray


def motion(model, x, qdot, qddot) -> Motion:
    """Derivatives of the transfer function at a solved configuration x (n_x,) for
    rates qdot, qddot (n_q,) of q = [q^r, q^d]."""
    n, nd = model.n_coordinates, model.n_dynamic
    x = np.asarray(x, dtype=float)
    v, a = np.empty(n), np.empty(n)
    Fd, Fdv, Fda = np.empty((n, nd)), np.empty((n, nd)), np.empty((n, nd))
    Fdd = np.empty((n, nd, nd))
    transfer.motion(model.arrays, x, np.asarray(qdot, dtype=float), np.asarray(qddot, dtype=float),
                    v, a, Fd, Fdv, Fdd, Fda)
    return Motion(x, v, a, Fd, Fdv, Fdd, Fda)
