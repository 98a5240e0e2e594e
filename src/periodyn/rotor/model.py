"""Rotor model: shaft sections on a line of stations, disks, bearings, seals and point
masses (builder :class:`Rotor`, compiled :class:`RotorModel`).

Every part is an independently modelled element (eq. 11-12 of Schwab & Meijaard 2001)
on the station coordinates. The linearized equations at spin speed Omega (rad/s)

    M q'' + (C0 + Omega C1) q' + (K0 + Omega K1 + Omega^2 K2) q = 0

follow from one transfer function per frame: the stationary frame (x = q) or the frame
co-rotating with the shaft, ``x = T(Omega t) q`` with T rotating every (y, z) and
(ry, rz) pair by the spin angle. Eq. (11-12) then add the Coriolis, centrifugal and
frame-velocity terms. With isotropic bearings and an axisymmetric shaft the co-rotating
equations do not depend on the spin angle (time-invariant); this is checked, not assumed.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..model.linearization import independent_terms
from ..model.elements import IndependentElement
from ..numerics.spectra import sample_angles
from ..system import RheoLinear
from .elements import (STATION_COORDINATES, Bearing, Disk, PointMass, ShaftSection, internal_damping, shaft_element,
                       spin_generator)

__all__ = ["Rotor", "RotorModel", "RotorEquations"]

FRAMES = ("rotating", "stationary")
_ANGLES = 4          # spin angles at which time-invariance of the co-rotating equations is checked


@dataclass(frozen=True)
class RotorEquations:
    """Linearized rotor equations in one frame: mass (n, n), damping [C0, C1],
    stiffness [K0, K1, K2] as powers of the spin speed Omega (rad/s); coordinate names;
    lateral (2, n_s, n): the y and z displacements (m) of every station, in the same
    frame, per coordinate (read by the whirl classification)."""

    frame: str
    mass: np.ndarray
    damping: tuple[np.ndarray, np.ndarray]
    stiffness: tuple[np.ndarray, np.ndarray, np.ndarray]
    coordinate_names: tuple[str, ...]
    lateral: np.ndarray

    def at(self, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(M, C, K) at spin speed ``speed`` (rad/s)."""
        C0, C1 = self.damping
        K0, K1, K2 = self.stiffness
        return self.mass, C0 + speed * C1, K0 + speed * K1 + speed**2 * K2


@dataclass(frozen=True, eq=False)
class RotorModel:
    """A compiled rotor: station positions (n_s,) m along the axis, coordinate names
    (4 n_s,) ``"<station>.y|z|ry|rz"``, independent elements with their coordinate
    indices, and whether every bearing is isotropic."""

    name: str
    stations: np.ndarray
    coordinate_names: tuple[str, ...]
    independent: tuple[tuple[IndependentElement, np.ndarray], ...]
    isotropic: bool

    frames = FRAMES

    @property
    def n(self) -> int:
        return len(self.coordinate_names)

    def _terms(self, frame: str, angles: np.ndarray):
        """Eq. (11-12) of every element at spin angles (p,): mass (p, n, n), damping
        and stiffness power lists."""
        n = self.n
        if frame == "stationary":
            T, Tv, Ta = np.eye(n)[None], np.zeros((1, n, n)), np.zeros((1, n, n))
        else:
            T, Tv, Ta = _spin_transfer(n, angles)
        M, C, K, _ = independent_terms(self.independent, T, Tv, Ta)
        return M, C, K

    def equations(self, frame: str = "rotating") -> RotorEquations:
        """Linearized equations in the ``rotating`` (co-rotating) or ``stationary`` frame."""
        if frame not in FRAMES:
            raise InputError(f"frame must be one of {FRAMES}, got {frame!r}")
        M, C, K = self._terms(frame, 2.0 * np.pi * np.arange(_ANGLES) / _ANGLES)
        drift = angle_drift([M, *C, *K])
        if drift > 1e-12:
            raise InputError(
                f"rotor '{self.name}': its co-rotating equations depend on the spin angle (an anisotropic bearing "
                f"or seal, relative variation {drift:.2g}); use frame='stationary', where an axisymmetric "
                "shaft on anisotropic supports is time-invariant, or rheo_linear() for the periodic co-rotating system")
        lateral = np.zeros((2, self.stations.size, self.n))
        k = np.arange(self.stations.size)
        for c in range(2):                      # y and z of station k: coordinates 4 k and 4 k + 1
            lateral[c, k, 4 * k + c] = 1.0
        return RotorEquations(frame, M[0], (C[0][0], C[1][0]), (K[0][0], K[1][0], K[2][0]), self.coordinate_names,
                              lateral)

    def rheo_linear(self, speed: float, samples: int) -> RheoLinear:
        """Co-rotating equations at spin speed (rad/s) sampled at ``samples`` spin angles
        over one revolution: periodic when a bearing is anisotropic (for Hill/Floquet)."""
        M, C, K = self._terms("rotating", sample_angles(samples))
        w = float(speed)
        return RheoLinear.from_samples(M, C[0] + w * C[1], K[0] + w * K[1] + w**2 * K[2], np.zeros(M.shape[:2]), w,
                                       coordinate_names=self.coordinate_names)


def angle_drift(parts) -> float:
    """Largest change over the spin angles (leading axis) of the sampled matrices
    ``parts``, relative to their largest entry: 0 for time-invariant equations."""
    scale = max(np.abs(a).max() for a in parts)
    return max(np.abs(a - a[0]).max() for a in parts) / scale if scale > 0 else 0.0


def _spin_transfer(n: int, angles: np.ndarray):
    """x = T(phi) q rotating each (y, z) and (ry, rz) pair by phi, with its derivatives
    at unit spin speed: T (p, n, n), T' = T S, T'' = T S S (S the rotation generator)."""
    p = angles.size
    c, s = np.cos(angles), np.sin(angles)
    T = np.zeros((p, n, n))
    for i in range(0, n, 2):
        T[:, i, i], T[:, i, i + 1], T[:, i + 1, i], T[:, i + 1, i + 1] = c, -s, s, c
    S = spin_generator(n)
    return T, T @ S, T @ S @ S


@dataclass
class Rotor:
    """Builder of a rotor on a straight shaft along x (SI units). Add shaft sections
    (stations are made at the element ends), then disks, bearings, seals and point
    masses at axial positions that coincide with a station; then :meth:`compile`."""

    name: str = "rotor"
    sections: list[ShaftSection] = field(default_factory=list)
    parts: list = field(default_factory=list)
    length_unit: float = 1.0  # metres per length unit of the input (a rotor file's [units] length), for messages

    def _length(self, x) -> str:
        """Axial position(s) x (m) as the input gave them: in m, or in its length unit with m after."""
        scaled = np.round(np.asarray(x, float) / self.length_unit, 6).tolist()
        if self.length_unit == 1.0:
            return f"{scaled} m"
        return f"{scaled} (file length units of {self.length_unit:g} m; {np.round(np.asarray(x, float), 6).tolist()} m)"

    def add_shaft(self, start: float, end: float, *, outer_diameter: float, E: float, density: float,
                  elements: int = 1, inner_diameter: float = 0.0, rotary_inertia: bool = True,
                  kelvin_voigt: float = 0.0) -> None:
        """A uniform shaft section from ``start`` to ``end`` (m) in ``elements`` equal
        Euler-Bernoulli elements (rotary inertia of the sections unless told), with
        internal Kelvin-Voigt damping time constant ``kelvin_voigt`` (s)."""
        self.sections.append(ShaftSection(float(start), float(end), float(outer_diameter), float(E), float(density),
                                          int(elements), float(inner_diameter), bool(rotary_inertia),
                                          float(kelvin_voigt)))

    def add_disk(self, at: float, mass: float, polar: float, diametral: float) -> None:
        """Rigid disk (kg, kg m^2, kg m^2) at axial position ``at`` (m)."""
        self.parts.append(Disk(float(at), mass, polar, diametral))

    def add_mass(self, at: float, mass: float) -> None:
        """Lateral point mass (kg) at ``at`` (m)."""
        self.parts.append(PointMass(float(at), mass))

    def add_bearing(self, bearing: Bearing) -> None:
        """A bearing or seal (see :class:`Bearing`, :func:`Seal`)."""
        if not isinstance(bearing, Bearing):
            raise InputError(f"add_bearing takes a Bearing or Seal(...), got {type(bearing).__name__}")
        self.parts.append(bearing)

    def stations(self, tol: float = 1e-9) -> np.ndarray:
        """Axial positions (m) of the stations, sorted; the sections must join end to end."""
        if not self.sections:
            raise InputError(f"rotor '{self.name}' has no shaft; add one with add_shaft(start, end, ...)")
        sections = sorted(self.sections, key=lambda sec: sec.start)
        for a, b in zip(sections, sections[1:]):
            if abs(a.end - b.start) > tol:
                raise InputError(f"rotor '{self.name}': shaft sections must join end to end, but one ends at "
                                 f"{self._length(a.end)} and the next starts at {self._length(b.start)}")
        x = [sections[0].start]
        for sec in sections:
            x.extend(np.linspace(sec.start, sec.end, sec.elements + 1)[1:])
        return np.array(x)

    def station_index(self, x: np.ndarray, at: float, what: str) -> int:
        """Index of the station at axial position ``at`` (m) among x (n_s,); ``what``
        names the part in the error when no station is there."""
        i = int(np.argmin(np.abs(x - at)))
        if abs(x[i] - at) > 1e-9 * max(1.0, float(np.ptp(x))):
            raise InputError(f"rotor '{self.name}': {what} at {self._length(at)} is not on a station; stations are "
                             f"at {self._length(x)} (split the shaft so that a station falls there)")
        return i

    def compile(self) -> RotorModel:
        """Element matrices on the station coordinates, with checks (missing stations,
        singular mass matrix)."""
        x = self.stations()
        names = tuple(f"s{i}.{c}" for i in range(x.size) for c in STATION_COORDINATES)

        def station(at, what):
            return self.station_index(x, at, what)

        independent = []
        for sec in self.sections:
            ends = np.linspace(sec.start, sec.end, sec.elements + 1)
            M, G, K = shaft_element(ends[1] - ends[0], sec.E, sec.density, sec.outer_diameter, sec.inner_diameter,
                                    sec.rotary_inertia)
            C, K1 = internal_damping(K, sec.kelvin_voigt)
            for a, b in zip(ends, ends[1:]):
                i, j = station(a, "shaft element end"), station(b, "shaft element end")
                independent.append((IndependentElement(f"shaft {a:.6g}-{b:.6g} m", names[4 * i:4 * i + 4] + names[4 * j:4 * j + 4],
                                                       stiffness=(K, K1), damping=(C, G), mass=M),
                                    np.r_[4 * i:4 * i + 4, 4 * j:4 * j + 4]))
        isotropic = True
        for part in self.parts:
            i = station(part.at, type(part).__name__.lower())
            if isinstance(part, Disk):
                M, G = part.matrices()
                el = IndependentElement(f"disk at {part.at:.6g} m", names[4 * i:4 * i + 4], damping=(np.zeros((4, 4)), G), mass=M)
                independent.append((el, np.arange(4 * i, 4 * i + 4)))
            elif isinstance(part, PointMass):
                el = IndependentElement(f"mass at {part.at:.6g} m", names[4 * i:4 * i + 2], mass=part.mass * np.eye(2))
                independent.append((el, np.arange(4 * i, 4 * i + 2)))
            else:
                K, C = part.matrices()
                isotropic &= part.isotropic
                idx = np.arange(4 * i, 4 * i + 2)
                if part.to is not None:
                    j = station(part.to, "bearing end 'to'")
                    idx = np.r_[idx, 4 * j:4 * j + 2]
                el = IndependentElement(f"bearing at {part.at:.6g} m", tuple(names[k] for k in idx),
                                        stiffness=(K,), damping=(C,))
                independent.append((el, idx))
        model = RotorModel(self.name, x, names, tuple(independent), bool(isotropic))
        _check_mass(model)
        return model


def _check_mass(model: RotorModel) -> None:
    M = model.equations("stationary").mass
    w, V = np.linalg.eigh(M)
    if w[0] > 1e-12 * w[-1]:
        return
    loose = [model.coordinate_names[i] for i in np.nonzero(np.abs(V[:, 0]) > 1e-6)[0]]
    raise InputError(f"rotor '{model.name}': the mass matrix is singular; coordinates {loose} carry no mass or "
                     "inertia. Give the shaft a density and keep rotary inertia on, or add disks/masses there")
