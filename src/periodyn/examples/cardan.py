"""Cardan drive shaft (Schwab & Meijaard 2001, section 4.4, Fig. 8-12).

A rigid input shaft along x turns at the prescribed angle theta = omega t; universal
joint 1 at the origin carries a flexible steel drive shaft (1.0 m, solid round r = 0.03 m,
rho = 7850 kg/m^3, E = 210 GPa, nu = 0.3, inextensible, two spatial beam elements with
lumped rotary inertia) inclined at the misalignment alpha in the x-y plane; universal
joint 2 at its far end drives a rigid output shaft parallel to the input (I_o = 0.345555
kg m^2, resisting torque M_o = 1060.288 N m). The drive shaft's yoke pins both lie along
global z in the reference, the input and output yoke pins in the x-y plane: the
Z-arrangement in which, for a rigid shaft, the output turns exactly with the input.
Joint centre 1 is fixed, joint centre 2 fixed laterally (its axial position follows from
the inextensible shaft). Kelvin-Voigt damping: one time constant for elongation and
bending, one for torsion, giving ``damping`` of critical in the first bending and the
first torsion mode of the straight shaft at rest.

Outputs (chosen by the model, in the frame that turns with the rigid drive shaft: a
massless copy of the input shaft and joint 1 driving a frame about the line through the
joint centres, so the harmonics keep the symmetry of the paper's Fig. 11-12):

- ``midpoint_deflection``: the midpoint's deflection from the line through the joint
  centres along the shaft's yoke-pin direction (the plane of the joints' bending moment,
  eq. 33), over the length (dimensionless);
- ``midpoint_deflection_normal``: the same in the other lateral direction;
- ``twist``: rotation of the shaft's driven (input) end relative to its far end about
  the shaft axis (rad; positive when transmitting power).

:func:`cardan_shaft` is the linearized model (an OmegaSplitModel for sweeps),
:func:`cardan_shaft_nonlinear` the full non-linear equations (4) of the same element
model for shooting, :func:`orbit_maxima` the maxima of Fig. 9-10 along its orbits.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ..errors import InputError
from ..model.linearization import omega_split
from ..model import BeamSection, Model
from ..model.spatial import axis_angle

__all__ = ["cardan_shaft", "cardan_shaft_nonlinear", "cardan_shaft_model", "orbit_maxima", "cardan_frequencies",
           "CARDAN"]

#: the paper's data (SI)
CARDAN = {"length": 1.0, "radius": 0.03, "density": 7850.0, "youngs_modulus": 210e9, "poisson_ratio": 0.3,
          "output_inertia": 0.345555, "output_torque": 1060.288, "omega_b": 766.0}


def _check(alpha, elements):
    if not (isinstance(alpha, (int, float)) and 0.0 <= alpha < np.pi / 3):
        raise InputError(f"alpha (misalignment, rad) must be in [0, pi/3), got {alpha!r}")
    if not isinstance(elements, int) or elements < 2 or elements % 2:
        raise InputError(f"elements must be an even integer >= 2 (a node at the midpoint), got {elements!r}")


def cardan_shaft_model(alpha: float = np.pi / 6, *, kelvin_voigt: float = 0.0, torsion_kelvin_voigt: float = 0.0,
                       output_torque: float = CARDAN["output_torque"], elements: int = 2,
                       rotary_inertia: bool = True):
    """The compiled element model; kelvin_voigt / torsion_kelvin_voigt: material damping
    time constants (s) of bending and torsion; elements: beam elements (even);
    rotary_inertia: the sections' rotary inertia (lumped at the nodes, as the paper).
    Torsion and bending of every element are dynamic, elongation rigid."""
    _check(alpha, elements)
    L, ca, sa = CARDAN["length"], np.cos(alpha), np.sin(alpha)
    chord = np.array([ca, sa, 0.0])
    incline = axis_angle((0.0, 0.0, 1.0), alpha)           # body x onto the drive shaft
    section = BeamSection.solid_circular(CARDAN["radius"], CARDAN["youngs_modulus"], CARDAN["poisson_ratio"],
                                         CARDAN["density"], rotary_inertia=rotary_inertia)
    m = Model("cardan_shaft", dimension=3)
    for name, rotation in (("ground_in", None), ("ground_out", None), ("ground_chord", incline)):
        m.add_orientation(name, rotation)
        m.fix(name)
    m.add_orientation("shaft_in")
    m.add_hinge("bearing_in", ("ground_in", "shaft_in"), axis=(1, 0, 0))
    m.prescribe("bearing_in.rotation")
    # the drive shaft: points and orientation nodes along the chord
    points, nodes = [f"P{i}" for i in range(elements + 1)], [f"R{i}" for i in range(elements + 1)]
    for i, (point, node) in enumerate(zip(points, nodes)):
        m.add_point(point, i * L / elements * chord)
        m.add_orientation(node, incline)
    m.fix("P0")
    m.fix(f"{points[-1]}.y")
    m.fix(f"{points[-1]}.z")
    modes = ("rigid",) + ("flexible",) * 5
    for i in range(elements):
        m.add_spatial_beam(f"beam{i + 1}", (points[i], points[i + 1]), (nodes[i], nodes[i + 1]), section,
                           modes=modes, y_axis=(-sa, ca, 0.0), lumped_rotary=True,
                           kelvin_voigt=(kelvin_voigt, torsion_kelvin_voigt) + (kelvin_voigt,) * 4)
    # joint 1: input pin in the shafts' plane, drive-shaft pin along z; joint 2 mirrored
    m.add_universal_joint("joint1", ("shaft_in", nodes[0]), axes=[(0, 1, 0), (0, 0, 1)])
    m.add_orientation("shaft_out")
    m.add_universal_joint("joint2", (nodes[-1], "shaft_out"), axes=[(0, 0, 1), (0, 1, 0)], rotation=incline)
    m.add_hinge("bearing_out", ("ground_out", "shaft_out"), axis=(1, 0, 0), torque=float(output_torque))
    m.add_rigid_body("shaft_out", np.diag([CARDAN["output_inertia"], 0.0, 0.0]))
    # massless frame turning with the rigid drive shaft, for the outputs
    m.add_orientation("frame", incline)
    m.add_hinge("frame_bearing", ("ground_chord", "frame"), axis=chord)
    m.add_universal_joint("frame_joint", ("shaft_in", "frame"), axes=[(0, 1, 0), (0, 0, 1)])
    mid = points[elements // 2]
    m.add_body_component("midpoint_deflection", (points[0], mid), "frame", (0.0, 0.0, 1.0), scale=L)
    m.add_body_component("midpoint_deflection_normal", (points[0], mid), "frame", (0.0, 1.0, 0.0), scale=L)
    m.add_hinge("twist", (nodes[-1], nodes[0]), axis=chord, misalignment="free")
    m.add_mode_output("twist", "twist.rotation")
    return m.compile()


def cardan_frequencies(model) -> dict[str, float]:
    """Undamped eigenfrequencies (rad/s) of the linearized model at rest (omega = 0,
    theta = 0): ``bending`` the lowest mode whose eigenvector lies in bending, ``torsion``
    the lowest in torsion (by the largest share of the torsion modes in its eigenvector)."""
    rest = omega_split(model, 1)  # the kernels the sweep's own model loads (linearize's would be one more)
    w2, vec = scipy.linalg.eigh(rest.stiffness[0, 0], rest.mass[0])
    twist = np.array([name.endswith(".torsion") for name in model.dynamic_names])
    share = (vec[twist] ** 2).sum(axis=0) / (vec**2).sum(axis=0)
    omega = np.sqrt(np.clip(w2, 0.0, None))
    return {"bending": float(omega[share < 0.5][0]), "torsion": float(omega[share >= 0.5][0])}


def _damped_model(alpha, damping, elements):
    """(compiled model with Kelvin-Voigt damping giving ``damping`` of critical in the
    first bending and torsion modes of the straight unloaded shaft, its metadata)."""
    if not (isinstance(damping, (int, float)) and 0 <= damping < 1):
        raise InputError(f"damping must be a fraction of critical in [0, 1), got {damping!r}")
    _check(alpha, elements)
    freq = cardan_frequencies(cardan_shaft_model(0.0, output_torque=0.0, elements=elements))
    # S_d = beta S gives modal damping beta * omega / 2 in a mode that strains only those modes
    beta_b, beta_t = 2.0 * damping / freq["bending"], 2.0 * damping / freq["torsion"]
    model = cardan_shaft_model(alpha, kelvin_voigt=beta_b, torsion_kelvin_voigt=beta_t, elements=elements)
    return model, {"omega_b": freq["bending"], "omega_t": freq["torsion"], "alpha": float(alpha),
                   "damping": float(damping), "kelvin_voigt": beta_b, "torsion_kelvin_voigt": beta_t}


def cardan_shaft(alpha: float = np.pi / 6, damping: float = 0.01, samples: int = 64, elements: int = 2):
    """OmegaSplitModel of the Cardan drive shaft at misalignment alpha (rad); damping:
    fraction of critical in the first bending and first torsion mode of the straight
    shaft at rest (alpha = 0, no load); samples: input angles per revolution; elements:
    beam elements (even). metadata: ``omega_b`` (first bending frequency of the
    undamped pinned shaft, rad/s, the reference frequency of sweeps), ``omega_t``
    (first torsion frequency), the Kelvin-Voigt time constants."""
    model, metadata = _damped_model(alpha, damping, elements)
    return omega_split(model, samples, name=f"cardan_shaft(alpha={alpha:.6g}, damping={damping})",
                       rebuild=lambda p: cardan_shaft(alpha, damping, p, elements), metadata=metadata)


def cardan_shaft_nonlinear(alpha: float = np.pi / 6, damping: float = 0.01, elements: int = 2):
    """The full non-linear equations (4) of the same Cardan shaft (``periodyn.element_dae``
    of the element model of :func:`cardan_shaft`, same damping): an ODE in the ten
    deformation modes of the two beams (torsion and four bending modes each) that
    ``periodyn.shooting(..., integrator="implicit")`` solves; ``.equations.model`` is the
    element model (outputs by ``periodyn.nonlinear.element_outputs``), ``.metadata`` as
    :func:`cardan_shaft`'s."""
    from ..nonlinear.elements import element_dae

    model, metadata = _damped_model(alpha, damping, elements)
    system = element_dae(model, name=f"cardan_shaft_nonlinear(alpha={alpha:.6g}, damping={damping})")
    system.metadata = metadata
    return system


def orbit_maxima(model, solution, samples: int = 360) -> dict[str, float]:
    """Maxima along a non-linear orbit of the Cardan shaft (a PeriodicSolution of
    :func:`cardan_shaft_nonlinear`, ``model`` its ``.equations.model``), at ``samples``
    times per period, the quantities of Fig. 9-10: ``deflection`` max |v/l| of the
    midpoint deflection, ``twist`` max phi (rad), each measured from the rigid motion
    (``periodyn.nonlinear.element_outputs``) as the linearized outputs are."""
    from ..nonlinear.elements import element_outputs

    t = np.arange(samples) * solution.period / samples
    y = element_outputs(model, solution.omega, t, solution(t))
    names = [o.name for o in model.outputs]
    return {"deflection": float(np.abs(y[:, names.index("midpoint_deflection")]).max()),
            "twist": float(y[:, names.index("twist")].max())}
