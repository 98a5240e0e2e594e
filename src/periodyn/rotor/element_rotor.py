"""Rotors on the element spine: an element model whose one input spins the shaft at
constant speed, linearized about that spin (in the co-rotating frame, as its deformation
modes are), turned into the constant-coefficient equations of :func:`periodyn.campbell`
(adapter :class:`ElementRotor`); and a :class:`~periodyn.rotor.Rotor` description built
from spatial beams (:func:`spatial_rotor_model`, :func:`spatial_rotor`).

The spatial-beam rotor (Schwab & Meijaard 2001, section 4.3, as SPACAR models it): a
motor hinge about x turns a drive node at the prescribed angle Omega t; a massless,
stiffness-free carrier beam from a fixed point on the axis to station 0 starts at the
drive node, so its four end rotations (flexible modes) are the co-rotating lateral
translation and tilt of station 0 (the rigid-body motion of the shaft on its bearings);
the shaft is a chain of spatial beams, inextensible and rigid in torsion, its four end
rotations per element flexible; disks are rigid bodies with their mass at the station;
bearings, seals and added masses are the rotor's independent elements (eq. 11-12) on the
stations' global (stationary) y and z. The linearized equations do not depend on the
carrier's length (first order: station 0 moves on a sphere about the fixed point).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.linearization import linearize, omega_split
from ..model import BeamSection, Model
from ..model.elements import IndependentElement
from ..model.model import CompiledModel
from .elements import Bearing, Disk, PointMass
from .model import Rotor, RotorEquations, angle_drift

__all__ = ["ElementRotor", "spatial_rotor_model", "spatial_rotor"]

_BENDING = {mode: "flexible" for mode in ("bending_z_p", "bending_z_q", "bending_y_p", "bending_y_q")}


@dataclass(frozen=True, eq=False)
class ElementRotor:
    """A rotor from a compiled element model: ``rotating`` holds its linearized
    equations in the model's dynamic coordinates (co-rotating; constant in the spin
    angle, which is checked), ``stations`` the point names whose lateral motion decides
    the whirl, ``model`` the compiled element model. Only the rotating frame exists
    (``equations("rotating")``)."""

    name: str
    coordinate_names: tuple[str, ...]
    stations: tuple[str, ...]
    rotating: RotorEquations
    model: CompiledModel

    isotropic = True
    frames = ("rotating",)

    @property
    def n(self) -> int:
        return len(self.coordinate_names)

    def equations(self, frame: str = "rotating") -> RotorEquations:
        """The co-rotating equations (the only frame of an element rotor)."""
        if frame != "rotating":
            raise InputError(f"rotor '{self.name}' is an element model whose coordinates turn with the shaft; only "
                             "frame='rotating' exists (for stationary-frame equations build a Rotor and compile it)")
        return self.rotating

    @classmethod
    def from_model(cls, model: CompiledModel, stations, *, samples: int = 4) -> "ElementRotor":
        """Adapter: the compiled element ``model`` with one input, the spin angle (the
        shaft along x, turning about +x at rate 1 per input angle), linearized at
        ``samples`` spin angles, whose M, C0 + Omega C1, K0 + Omega K1 + Omega^2 K2 must
        not depend on the angle (isotropic supports; InputError otherwise). stations:
        point names on the shaft; their co-rotating y and z are read at spin angle 0,
        where the co-rotating frame is the global one."""
        if not isinstance(model, CompiledModel) or model.dimension != 3:
            raise InputError(f"ElementRotor.from_model takes a compiled spatial Model, got {type(model).__name__}")
        if model.n_inputs != 1:
            raise InputError(f"model '{model.name}' has inputs {list(model.input_names)}; a rotor needs exactly one, "
                             "the spin angle (prescribe a hinge about the shaft axis with rate 1)")
        index = {c: i for i, c in enumerate(model.coordinate_names)}
        stations = tuple(stations)
        missing = [s for s in stations if f"{s}.y" not in index]
        if missing or not stations:
            raise InputError(f"model '{model.name}': stations {missing or '[]'} are not points of the model; give the "
                             "names of the points on the shaft")
        split = omega_split(model, samples)
        drift = angle_drift([split.mass, *split.damping, *split.stiffness])
        if drift > 1e-9:   # rounding of the omega-power recovery: 4e-15 (5 elements) to 2e-12 (20) measured
            raise InputError(
                f"rotor '{model.name}': its co-rotating equations depend on the spin angle (relative variation "
                f"{drift:.2g}: an anisotropic bearing or seal, or a non-axisymmetric shaft); sweep the "
                "element model's periodic system instead (periodyn.model.linearization.omega_split, Hill's method) or use a "
                "Rotor in frame='stationary'")
        damping = [split.damping[k][0] if k < len(split.damping) else np.zeros_like(split.mass[0]) for k in range(2)]
        stiffness = [split.stiffness[k][0] if k < len(split.stiffness) else np.zeros_like(split.mass[0])
                     for k in range(3)]
        Fd = linearize(model, 0.0, 1).transfer_jacobian[0]
        lateral = np.stack([Fd[[index[f"{s}.{c}"] for s in stations]] for c in "yz"])
        eq = RotorEquations("rotating", split.mass[0], tuple(damping), tuple(stiffness), model.dynamic_names, lateral)
        return cls(model.name, model.dynamic_names, stations, eq, model)


def _section(sec) -> BeamSection:
    """Spatial beam section of a rotor's (hollow) circular shaft section: bending
    stiffness, mass and rotary inertias (the shaft is inextensible and rigid in torsion)."""
    area = np.pi / 4.0 * (sec.outer_diameter**2 - sec.inner_diameter**2)
    second = np.pi / 64.0 * (sec.outer_diameter**4 - sec.inner_diameter**4)
    transverse = sec.density * second if sec.rotary_inertia else 0.0
    return BeamSection(EI_y=sec.E * second, EI_z=sec.E * second, mass_per_length=sec.density * area,
                       polar_inertia=2.0 * sec.density * second, rotary_inertia_y=transverse,
                       rotary_inertia_z=transverse)


def spatial_rotor_model(rotor: Rotor, *, lumped_rotary: bool = False, carrier_length: float | None = None
                        ) -> CompiledModel:
    """The compiled spatial element model of ``rotor`` (module docstring): points
    ``P<i>`` and orientation nodes ``R<i>`` at the stations; carrier_length (m, default
    the shaft's length) places the carrier's fixed point; lumped_rotary: the shaft's
    rotary inertia lumped at the nodes (else consistent, as the Rotor's elements)."""
    if not isinstance(rotor, Rotor):
        raise InputError(f"spatial_rotor_model takes a Rotor builder, got {type(rotor).__name__}")
    x = rotor.stations()
    length = float(np.ptp(x)) if carrier_length is None else float(carrier_length)
    if not (np.isfinite(length) and length > 0):
        raise InputError(f"carrier_length must be a positive length in m, got {carrier_length!r}")
    m = Model(rotor.name, dimension=3)
    m.add_orientation("ground")
    m.fix("ground")
    m.add_orientation("drive")
    m.add_hinge("motor", ("ground", "drive"), axis=(1.0, 0.0, 0.0))
    m.prescribe("motor.rotation", rate=1.0)
    m.add_point("pivot", (x[0] - length, 0.0, 0.0))
    m.fix("pivot")
    for i, xi in enumerate(x):
        m.add_point(f"P{i}", (xi, 0.0, 0.0))
        m.add_orientation(f"R{i}")
    m.add_spatial_beam("carrier", ("pivot", "P0"), ("drive", "R0"), BeamSection(), modes=_BENDING)
    for sec in rotor.sections:
        ends = np.linspace(sec.start, sec.end, sec.elements + 1)
        section = _section(sec)
        for a, b in zip(ends, ends[1:]):
            i, j = rotor.station_index(x, a, "shaft element end"), rotor.station_index(x, b, "shaft element end")
            m.add_spatial_beam(f"shaft{i}", (f"P{i}", f"P{j}"), (f"R{i}", f"R{j}"), section, modes=_BENDING,
                               lumped_rotary=lumped_rotary, kelvin_voigt=sec.kelvin_voigt)
    for part in rotor.parts:
        i = rotor.station_index(x, part.at, type(part).__name__.lower())
        lateral = (f"P{i}.y", f"P{i}.z")
        if isinstance(part, Disk):
            m.add_rigid_body(f"R{i}", np.diag([part.polar, part.diametral, part.diametral]), point=f"P{i}",
                             mass=part.mass)
        elif isinstance(part, PointMass):
            m.add_independent(IndependentElement(f"mass at {part.at:.6g} m", lateral, mass=part.mass * np.eye(2)))
        elif isinstance(part, Bearing):
            K, C = part.matrices()
            if part.to is not None:
                j = rotor.station_index(x, part.to, "bearing end 'to'")
                lateral += (f"P{j}.y", f"P{j}.z")
            m.add_independent(IndependentElement(f"bearing at {part.at:.6g} m", lateral, stiffness=(K,),
                                                 damping=(C,)))
    return m.compile()


def spatial_rotor(rotor: Rotor, *, samples: int = 4, lumped_rotary: bool = False,
                  carrier_length: float | None = None) -> ElementRotor:
    """``rotor`` built from spatial beams (:func:`spatial_rotor_model`) as an
    :class:`ElementRotor` for :func:`periodyn.campbell`; samples: spin angles at which
    the equations are checked to be constant."""
    model = spatial_rotor_model(rotor, lumped_rotary=lumped_rotary, carrier_length=carrier_length)
    return ElementRotor.from_model(model, [f"P{i}" for i in range(rotor.stations().size)], samples=samples)
