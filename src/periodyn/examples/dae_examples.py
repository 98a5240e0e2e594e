"""The four DAE examples of Ju, Fan & Zhu (2021), App. B (eqs. 61-82), and a Duffing ODE.

The paper's parameter values were lost with its main text; the defaults below are our
choices (SI units) and are repeated, with units and sweep ranges, in ``sweeps/dae_*.toml``
(a test checks that both agree). Coordinates are centre-of-mass (x, y, phi) per rod and
(x, y) for the slider; gravity g acts along -y.

Sign corrections (slider-chain pendulum, eqs. 73, 77-79): as printed, the interior force
``-k_hat (phi_{i-1} - 2 phi_i + phi_{i+1})`` is a destabilising spring and
``-eps_hat (phi'_{i-1} - 2 phi'_i + phi'_{i+1})`` a negative damping, and eq. (77) has the
opposite sign of ``-dV/dphi_2``. We derive the forces from the energies (71)-(72) and the
Rayleigh dissipation ``D = eps_hat/2 [phi_2'^2 + sum_{i>=3} (phi_i' - phi_{i-1}')^2]``:
``f_phi2 = -k_hat (phi_2 + pi/2) + k_hat (phi_3 - phi_2) - eps_hat (2 phi_2' - phi_3')``,
``f_phii = k_hat (phi_{i-1} - 2 phi_i + phi_{i+1}) + eps_hat (phi'_{i-1} - 2 phi'_i + phi'_{i+1})``,
``f_phi41 = -k_hat (phi_41 - phi_40) - eps_hat (phi'_41 - phi'_40)`` (eq. 79 as printed).
"""

from __future__ import annotations

import numpy as np

from ..dae import DAE
from ..errors import InputError
from ..model.rigid2d import PlanarSystem
from ._arguments import require_physical as _check

__all__ = ["rod_pendulum", "inverted_pendulum", "slider_rod_pendulum", "slider_chain_pendulum", "duffing"]

G = 9.81


def rod_pendulum(m1: float = 1.0, l: float = 1.0, eps1: float = 0.04, f: float = 0.15, g: float = G) -> DAE:
    """Rod pinned at its end (eqs. 61-62): m1 kg, l m, viscous torque eps1 N m s/rad,
    torque f cos(w t) N m (parameter "f"). Hanging rest position phi = -pi/2;
    small-swing frequency sqrt(3 g / (2 l)) = 3.84 rad/s with the defaults."""
    _check("rod_pendulum", {"m1": m1, "l": l}, {"eps1": eps1, "g": g}, {"f": f})
    s = PlanarSystem(g, "rod_pendulum")
    s.add_parameter("f", f)
    b = s.add_body(m1, m1 * l * l / 12, "rod")
    s.add_revolute(b, (-l / 2, 0.0))
    phi = s.coordinate(b, "phi")
    s.add_spring(phi, c=eps1)
    s.add_load(phi, cos=1.0, parameter="f")
    return s.build(q0=[0.0, -l / 2, -np.pi / 2])


def inverted_pendulum(m1: float = 1.0, l: float = 1.0, eps: float = 0.05, kappa: float = 20.0, p: float = 0.05,
                      g: float = G) -> DAE:
    """Inverted rod on a vertically moving base (eqs. 63-64): pivot at (0, -p sin w t)
    (parameter "p", m), cubic torsional spring kappa (pi/2 - phi)^3 (N m/rad^3) holding the
    rod against gravity, viscous torque eps N m s/rad. The upright position is unstable;
    the rest positions are the two tilted equilibria, q0 the one with phi > pi/2."""
    _check("inverted_pendulum", {"m1": m1, "l": l, "kappa": kappa, "g": g}, {"eps": eps}, {"p": p})
    s = PlanarSystem(g, "inverted_pendulum")
    s.add_parameter("p", p)
    b = s.add_body(m1, m1 * l * l / 12, "rod")
    s.add_revolute(b, (-l / 2, 0.0), base_sin=(0.0, -1.0), parameter="p")
    phi = s.coordinate(b, "phi")
    s.add_spring(phi, k3=kappa, c=eps, offset=np.pi / 2)
    th = 0.5  # tilt of the static equilibrium: kappa th^3 = m g l/2 sin(th)
    for _ in range(50):
        r = kappa * th ** 3 - 0.5 * m1 * g * l * np.sin(th)
        th -= r / (3 * kappa * th ** 2 - 0.5 * m1 * g * l * np.cos(th))
    ph0 = np.pi / 2 + th
    return s.build(q0=[0.5 * l * np.cos(ph0), 0.5 * l * np.sin(ph0), ph0])


def slider_rod_pendulum(m1: float = 1.0, m2: float = 0.5, l: float = 0.5, k1: float = 100.0, c1: float = 0.5,
                        k2: float = 0.5, c2: float = 0.005, f: float = 1.0, g: float = G) -> DAE:
    """Slider on a horizontal line with a hanging rod (eqs. 65-69): slider m1 kg on spring
    k1 N/m, damper c1 N s/m, force f cos(w t) N (parameter "f"); rod m2 kg, l m pinned to
    the slider, torsional spring k2 N m/rad to the hanging position, damper c2 N m s/rad."""
    _check("slider_rod_pendulum", {"m1": m1, "m2": m2, "l": l}, {"k1": k1, "c1": c1, "k2": k2, "c2": c2, "g": g},
           {"f": f})
    s = PlanarSystem(g, "slider_rod_pendulum")
    s.add_parameter("f", f)
    b1 = s.add_body(m1, None, "slider")
    b2 = s.add_body(m2, m2 * l * l / 12, "rod")
    s.add_slider(b1, normal=(0.0, 1.0))
    s.add_revolute(b2, (-l / 2, 0.0), b1, (0.0, 0.0))
    x1 = s.coordinate(b1, "x")
    s.add_spring(x1, k=k1, c=c1)
    s.add_load(x1, cos=1.0, parameter="f")
    s.add_spring(s.coordinate(b2, "phi"), k=k2, c=c2, offset=-np.pi / 2)
    return s.build(q0=[0.0, 0.0, 0.0, -l / 2, -np.pi / 2])


def slider_chain_pendulum(n_rods: int = 40, m1: float = 1.0, m: float = 0.025, l: float = 0.025,
                          kappa1: float = 100.0, eps1: float = 2.0, kappa_hat: float = 0.05,
                          eps_hat: float = 5e-4, p: float = 1.0, g: float = G) -> DAE:
    """Slider with a chain of ``n_rods`` rods (eqs. 70-82; 40 rods: n = 122, m = 81):
    slider m1 kg on spring kappa1 N/m, damper eps1 N s/m, force p cos(w t) N (parameter
    "p"); rods m kg, l m, torsional springs kappa_hat N m/rad and dampers eps_hat
    N m s/rad from rod 2 to the hanging direction and between neighbouring rods. Forces
    follow the energies (71)-(72) (see the module docstring for the sign corrections)."""
    if isinstance(n_rods, bool) or not isinstance(n_rods, (int, np.integer)) or n_rods < 1:
        raise InputError(f"slider_chain_pendulum: n_rods must be an integer >= 1 (the number of rods of the chain), "
                         f"got {n_rods!r}")
    _check("slider_chain_pendulum", {"m1": m1, "m": m, "l": l},
           {"kappa1": kappa1, "eps1": eps1, "kappa_hat": kappa_hat, "eps_hat": eps_hat, "g": g}, {"p": p})
    s = PlanarSystem(g, "slider_chain_pendulum")
    s.add_parameter("p", p)
    b1 = s.add_body(m1, None, "slider")
    s.add_slider(b1, normal=(0.0, 1.0))
    x1 = s.coordinate(b1, "x")
    s.add_spring(x1, k=kappa1, c=eps1)
    s.add_load(x1, cos=1.0, parameter="p")
    rods = [s.add_body(m, m * l * l / 12, f"rod{i + 2}") for i in range(n_rods)]
    s.add_revolute(rods[0], (-l / 2, 0.0), b1, (0.0, 0.0))
    s.add_spring(s.coordinate(rods[0], "phi"), k=kappa_hat, c=eps_hat, offset=-np.pi / 2)
    for a, b in zip(rods[:-1], rods[1:]):
        s.add_revolute(b, (-l / 2, 0.0), a, (l / 2, 0.0))
        s.add_spring(s.coordinate(b, "phi"), s.coordinate(a, "phi"), k=kappa_hat, c=eps_hat)
    q0 = [0.0, 0.0]
    for i in range(n_rods):
        q0 += [0.0, -(i + 0.5) * l, -np.pi / 2]
    return s.build(q0=q0)


def duffing(zeta: float = 0.05, alpha: float = 1.0, F: float = 0.1, omega0: float = 1.0) -> DAE:
    """Forced Duffing oscillator ``x'' + 2 zeta omega0 x' + omega0^2 x + alpha x^3 = F cos(w t)``
    (unit mass) as a constraint-free ``periodyn.DAE`` with analytic Jacobians; parameter "F"."""
    _check("duffing", {"omega0": omega0}, {"zeta": zeta}, {"alpha": alpha, "F": F})

    def force(q, qd, t, w, P):
        return np.array([-2 * zeta * omega0 * qd[0] - omega0 ** 2 * q[0] - alpha * q[0] ** 3 + P["F"] * np.cos(w * t)])

    def force_jacobian(q, qd, t, w, P):
        return (np.array([[-omega0 ** 2 - 3 * alpha * q[0] ** 2]]), np.array([[-2 * zeta * omega0]]))

    return DAE(np.eye(1), force, force_jacobian=force_jacobian, parameters={"F": F}, coordinate_names=("x",),
               name="duffing", phase_forcing=True)
