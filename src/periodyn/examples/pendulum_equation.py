"""Pendulum with an elliptic motion of its support point (Schwab & Meijaard sec. 4.1).

Linearized equation (29) about phi = 0, a forced damped Mathieu equation:

    dphi'' + 2 zeta w0 dphi' + [w0^2 + (1+e) rho w^2 cos(w t)] dphi
        = -2 zeta w0 w + (1-e) rho w^2 sin(w t),

w0 = sqrt(g/l), rho = r/l. Split in powers of the driving speed w:
C = C0, K = K0 + w^2 K2(theta), f = w f1 + w^2 f2(theta) with theta = w t.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..system import OmegaSplitModel

__all__ = ["pendulum", "pendulum_nonlinear"]


def pendulum(*, length: float = 1.0, radius: float = 0.5, eccentricity: float = 0.5, zeta: float = 0.01,
             g: float = 9.81, samples: int = 32) -> OmegaSplitModel:
    """Linearized elliptic pendulum, eq. (29): one coordinate ``phi`` (rad), output ``phi``.

    length l (m), pinion radius r (m), eccentricity factor e (-), relative damping zeta
    (-), gravity g (m/s^2). metadata["omega0"] = sqrt(g/l) (rad/s) is the reference
    frequency of the paper's figures.
    """
    for name, value in (("length", length), ("radius", radius), ("g", g)):
        if not np.isfinite(value) or value <= 0:
            raise InputError(f"pendulum {name} must be positive, got {value!r}")
    if zeta < 0 or not np.isfinite(zeta):
        raise InputError(f"pendulum zeta must be >= 0 (relative damping), got {zeta!r}")
    w0 = np.sqrt(g / length)
    rho = radius / length
    return OmegaSplitModel.from_functions(
        mass=lambda th: 1.0,
        damping=[lambda th: 2 * zeta * w0],
        stiffness=[lambda th: w0**2, lambda th: 0.0, lambda th: (1 + eccentricity) * rho * np.cos(th)],
        force=[lambda th: 0.0, lambda th: -2 * zeta * w0, lambda th: (1 - eccentricity) * rho * np.sin(th)],
        samples=samples, coordinate_names=("phi",), name="pendulum",
        metadata={"omega0": float(w0), "length": length, "radius": radius, "eccentricity": eccentricity,
                  "zeta": zeta, "g": g},
    )


def pendulum_nonlinear(*, length: float = 1.0, radius: float = 0.5, eccentricity: float = 0.5, zeta: float = 0.01,
                       g: float = 9.81):
    """Full non-linear elliptic pendulum, eq. (28), as a one-coordinate ODE ``periodyn.DAE``:

        phi'' + 2 zeta w0 (phi' + w) + w0^2 sin(phi) + rho w^2 [sin(phi - w t) + e sin(phi + w t)] = 0,

    for shooting / continuation against the linearized eq. (29) (``pendulum``)."""
    from ..dae import DAE
    from ._arguments import require_physical

    require_physical("pendulum_nonlinear", {"length": length, "radius": radius, "g": g}, {"zeta": zeta},
                     {"eccentricity": eccentricity})

    w0 = np.sqrt(g / length)
    rho = radius / length

    def force(q, qd, t, omega):
        phi = q[0]
        return np.array([-(2 * zeta * w0 * (qd[0] + omega) + w0**2 * np.sin(phi)
                           + rho * omega**2 * (np.sin(phi - omega * t) + eccentricity * np.sin(phi + omega * t)))])

    def force_jacobian(q, qd, t, omega):
        phi = q[0]
        dq = -(w0**2 * np.cos(phi) + rho * omega**2 * (np.cos(phi - omega * t) + eccentricity * np.cos(phi + omega * t)))
        return np.array([[dq]]), np.array([[-2 * zeta * w0]])

    return DAE(np.eye(1), force, force_jacobian=force_jacobian, coordinate_names=("phi",), name="pendulum_nonlinear")
