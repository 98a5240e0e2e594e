"""Rotor elements as data, in the stationary frame (SI units).

Every station (node on the shaft axis, x along the axis) has four coordinates, in this
order: lateral displacements ``y``, ``z`` (m) and small section rotations ``ry``,
``rz`` about the y and z axes (rad), so that ``rz = dy/dx`` and ``ry = -dz/dx``. The
shaft spins at Omega about +x (from y towards z). Each element becomes an
:class:`periodyn.model.IndependentElement` (eq. 11-12 of Schwab & Meijaard 2001): a
mass matrix, damping as powers of Omega ``[C, G]`` (G the gyroscopic matrix) and a
stiffness, all on the station coordinates it touches.

Shaft element: Euler-Bernoulli (no shear deformation), cubic Hermite interpolation of
both bending planes; consistent translational mass, rotary inertia of the cross-sections
(rho I per length about each transverse axis), gyroscopic coupling of the polar inertia
(rho J = 2 rho I per length) and bending stiffness, each integrated by Gauss-Legendre
quadrature of the shape functions (exact for these polynomials).

The gyroscopic terms follow from the kinetic energy of a spinning section with small
tilts: T = 1/2 J (Omega - rz' ry)^2 + 1/2 I (ry'^2 + rz'^2), whose term linear in Omega,
``-Omega J rz' ry``, gives ``G = G^ - G^T`` with ``G^ = -J outer(rz, ry)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["STATION_COORDINATES", "shaft_element", "spin_generator", "internal_damping", "Disk", "Bearing", "Seal", "PointMass", "ShaftSection"]

STATION_COORDINATES = ("y", "z", "ry", "rz")

_HERMITE = (lambda s: 1 - 3 * s**2 + 2 * s**3, lambda s: 3 * s**2 - 2 * s**3,
            lambda s: s - 2 * s**2 + s**3, lambda s: -(s**2) + s**3)
_HERMITE_1 = (lambda s: -6 * s + 6 * s**2, lambda s: 6 * s - 6 * s**2,
              lambda s: 1 - 4 * s + 3 * s**2, lambda s: -2 * s + 3 * s**2)
_HERMITE_2 = (lambda s: -6 + 12 * s, lambda s: 6 - 12 * s, lambda s: -4 + 6 * s, lambda s: -2 + 6 * s)


def _positive(name: str, value, allow_zero: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not np.isfinite(v) or v < 0.0 or (v == 0.0 and not allow_zero):
        raise InputError(f"{name} must be a {'non-negative' if allow_zero else 'positive'} finite number, got {value!r}")
    return v


def _interpolation(functions, length: float, derivative: int, s: np.ndarray):
    """Rows y(s), z(s) (or their x-derivatives) over the 8 element coordinates
    [y1, z1, ry1, rz1, y2, z2, ry2, rz2]; (2, 8, len(s))."""
    h = np.array([f(s) for f in functions]) / length**derivative
    out = np.zeros((2, 8, s.size))
    out[0, 0], out[0, 4], out[0, 3], out[0, 7] = h[0], h[1], length * h[2], length * h[3]
    out[1, 1], out[1, 5], out[1, 2], out[1, 6] = h[0], h[1], -length * h[2], -length * h[3]
    return out


def shaft_element(length: float, E: float, density: float, outer_diameter: float, inner_diameter: float = 0.0,
                  rotary_inertia: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mass, gyroscopic (per unit Omega) and stiffness matrices (8, 8) of a uniform
    circular (hollow) shaft element of ``length`` (m), Young's modulus E (Pa), density
    (kg/m^3), diameters (m); kg / kg m^2, kg m^2 (N m s), N/m / N m/rad."""
    s, w = np.polynomial.legendre.leggauss(6)
    s, w = 0.5 * (s + 1.0), 0.5 * w * length          # dx weights
    area = np.pi / 4.0 * (outer_diameter**2 - inner_diameter**2)
    inertia = np.pi / 64.0 * (outer_diameter**4 - inner_diameter**4)
    N = _interpolation(_HERMITE, length, 0, s)
    slope = _interpolation(_HERMITE_1, length, 1, s)
    curvature = _interpolation(_HERMITE_2, length, 2, s)
    ry, rz = -slope[1], slope[0]

    def gram(a, b):
        return (a * w) @ b.T

    mass = density * area * (gram(N[0], N[0]) + gram(N[1], N[1]))
    if rotary_inertia:
        mass += density * inertia * (gram(ry, ry) + gram(rz, rz))
    half = -2.0 * density * inertia * gram(rz, ry)
    stiffness = E * inertia * (gram(curvature[0], curvature[0]) + gram(curvature[1], curvature[1]))
    return mass, half - half.T, stiffness


def spin_generator(n: int) -> np.ndarray:
    """S (n, n) with d/dt T(Omega t) = Omega T S for T rotating each (y, z) and (ry, rz)
    pair by the spin angle (n even)."""
    S = np.zeros((n, n))
    for i in range(0, n, 2):
        S[i, i + 1], S[i + 1, i] = -1.0, 1.0
    return S


def internal_damping(stiffness: np.ndarray, beta: float) -> tuple[np.ndarray, np.ndarray]:
    """Stationary-frame damping and Omega^1 stiffness of Kelvin-Voigt damping beta (s)
    acting in the co-rotating frame: f = -beta K (u' - Omega S u), so C = beta K and
    K1 = -beta K S (the circulatory term behind internal-damping instability)."""
    return beta * stiffness, -beta * stiffness @ spin_generator(stiffness.shape[0])


@dataclass(frozen=True)
class ShaftSection:
    """Uniform shaft from axial position ``start`` to ``end`` (m), split into ``elements``
    equal beam elements; E (Pa), density (kg/m^3), diameters (m); kelvin_voigt: material
    damping time constant beta (s), sigma = E (eps + beta eps') acting on the bending
    rates seen in the co-rotating frame (internal, rotating damping)."""

    start: float
    end: float
    outer_diameter: float
    E: float
    density: float
    elements: int = 1
    inner_diameter: float = 0.0
    rotary_inertia: bool = True
    kelvin_voigt: float = 0.0

    def __post_init__(self):
        if not self.end > self.start:
            raise InputError(f"shaft section from {self.start} m to {self.end} m: end must lie beyond start")
        for name in ("outer_diameter", "E"):
            _positive(f"shaft section {name}", getattr(self, name))
        _positive("shaft section density", self.density, allow_zero=True)
        _positive("shaft section kelvin_voigt", self.kelvin_voigt, allow_zero=True)
        if not 0.0 <= self.inner_diameter < self.outer_diameter:
            raise InputError(f"shaft section: inner diameter {self.inner_diameter} m must be in [0, outer diameter)")
        if int(self.elements) != self.elements or self.elements < 1:
            raise InputError(f"shaft section: elements must be a positive integer, got {self.elements!r}")


@dataclass(frozen=True)
class Disk:
    """Rigid disk at axial position ``at`` (m): mass (kg), polar and diametral moments of
    inertia (kg m^2) about its centre on the shaft axis."""

    at: float
    mass: float
    polar: float
    diametral: float

    def __post_init__(self):
        for name in ("mass", "polar", "diametral"):
            _positive(f"disk at {self.at} m: {name}", getattr(self, name), allow_zero=True)

    def matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """Mass and gyroscopic (per unit Omega) matrices (4, 4) on (y, z, ry, rz)."""
        gyro = np.zeros((4, 4))
        gyro[2, 3], gyro[3, 2] = self.polar, -self.polar
        return np.diag([self.mass, self.mass, self.diametral, self.diametral]), gyro


@dataclass(frozen=True)
class PointMass:
    """Lumped mass (kg) moving with the lateral displacement at ``at`` (m), e.g. the part
    of a seal's fluid mass that is added to the shaft."""

    at: float
    mass: float

    def __post_init__(self):
        _positive(f"point mass at {self.at} m", self.mass)


@dataclass(frozen=True)
class Bearing:
    """Linear bearing at ``at`` (m) acting on (y, z) in the stationary frame:
    ``f = -K [y, z] - C [y', z']`` with K = [[kyy, kyz], [kzy, kzz]] (N/m) and
    C = [[cyy, cyz], [czy, czz]] (N s/m). Cross-coupling is allowed; isotropic means
    K and C of the form [[a, b], [-b, a]] (then the bearing looks the same from the
    co-rotating frame). With ``to`` (m) it is a spring/damper on the displacement of
    station ``at`` relative to station ``to`` instead of to ground."""

    at: float
    kyy: float
    kzz: float
    kyz: float = 0.0
    kzy: float = 0.0
    cyy: float = 0.0
    czz: float = 0.0
    cyz: float = 0.0
    czy: float = 0.0
    to: float | None = None

    def __post_init__(self):
        values = (self.kyy, self.kzz, self.kyz, self.kzy, self.cyy, self.czz, self.cyz, self.czy)
        if not all(np.isfinite(float(v)) for v in values):
            raise InputError(f"bearing at {self.at} m: coefficients must be finite numbers, got {values}")
        if self.kyy < 0 or self.kzz < 0 or self.cyy < 0 or self.czz < 0:
            raise InputError(f"bearing at {self.at} m: direct stiffness and damping must be non-negative")
        if self.to is not None and self.to == self.at:
            raise InputError(f"bearing at {self.at} m: 'to' must be another station (or None for ground)")

    def matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness and damping on (y, z) at ``at`` (2, 2), or on (y, z) at ``at`` then
        at ``to`` (4, 4) for a relative spring/damper."""
        K = np.array([[self.kyy, self.kyz], [self.kzy, self.kzz]])
        C = np.array([[self.cyy, self.cyz], [self.czy, self.czz]])
        if self.to is None:
            return K, C
        relative = np.array([[1.0, -1.0], [-1.0, 1.0]])
        return np.kron(relative, K), np.kron(relative, C)

    @property
    def isotropic(self) -> bool:
        K, C = self.matrices()
        K, C = K[:2, :2], C[:2, :2]
        return all(np.isclose(A[0, 0], A[1, 1]) and np.isclose(A[0, 1], -A[1, 0]) for A in (K, C))


def Seal(at: float, K: float, k: float, C: float, c: float) -> Bearing:
    """Annular seal of eq. (30): direct and cross-coupled stiffness K, k (N/m) and
    damping C, c (N s/m), ``f = -[[K, k], [-k, K]] u - [[C, c], [-c, C]] u'`` on the
    stationary-frame lateral displacement u = (y, z). The coefficient matrices are
    unchanged by a rotation about the shaft axis; seen from the co-rotating frame the
    law gains the Omega terms of eq. (11) from the frame's motion (checked against
    Table I, which they reproduce)."""
    return Bearing(at, K, K, k, -k, C, C, c, -c)
