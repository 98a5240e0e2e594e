"""Outputs chosen by the model: functionals y(x) of the nodal coordinates whose
linearization ``G = y_x F_q^d`` maps the small vibration q^d to the output.

Kinds: a midpoint deflection (distance of a point from the line through two others over
a reference length), any nodal coordinate (over a scale), the relative rotation of two
angle nodes, and any deformation mode of an element (over a scale). Each is compiled to
an :class:`OutputMap` (packed nodal-coordinate indices and parameters) whose
:meth:`OutputMap.gradient` gives y_x on those coordinates.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..kernels.mechanism.outputs import body_component, midpoint_deflection

__all__ = ["CoordinateOutput", "RelativeRotation", "ModeOutput", "BodyComponent", "OutputMap"]

def check_scale(name: str, scale) -> float:
    """scale as a float; InputError unless finite and non-zero."""
    s = float(scale)
    if not np.isfinite(s) or s == 0.0:
        raise InputError(f"output '{name}': scale must be a finite non-zero number, got {scale!r}")
    return s


KINDS = ("midpoint_deflection", "coordinate", "relative_rotation", "mode", "body_component")


@dataclass(frozen=True)
class CoordinateOutput:
    """Output: nodal coordinate ``coordinate`` (m or rad) divided by ``scale``."""

    name: str
    coordinate: str
    scale: float = 1.0

    kind = "coordinate"

    def coordinates(self) -> list[str]:
        return [self.coordinate]


@dataclass(frozen=True)
class RelativeRotation:
    """Output: rotation of angle node ``angles[1]`` relative to ``angles[0]`` (rad)."""

    name: str
    angles: tuple[str, str]

    kind = "relative_rotation"

    def coordinates(self) -> list[str]:
        return list(self.angles)


@dataclass(frozen=True)
class ModeOutput:
    """Output: deformation mode ``"<element>.<mode>"`` divided by ``scale``; element is
    the element's index in the model and ``index`` the mode's index in the element."""

    name: str
    mode: str
    element: int
    index: int
    element_coordinates: tuple[str, ...]
    scale: float = 1.0

    kind = "mode"

    def coordinates(self) -> list[str]:
        return list(self.element_coordinates)


@dataclass(frozen=True)
class BodyComponent:
    """Output: the position of point ``points[1]`` relative to ``points[0]`` in the frame of
    orientation node ``orientation``, its component along ``direction`` (3,) (unit, body
    components), divided by ``scale`` (e.g. the lateral deflection of a shaft's midpoint
    in the frame of a co-rotating end node, over the shaft length)."""

    name: str
    points: tuple[str, str]
    orientation: str
    direction: tuple[float, float, float]
    scale: float = 1.0

    kind = "body_component"

    def coordinates(self) -> list[str]:
        a, m = ([f"{p}.{c}" for c in "xyz"] for p in self.points)
        return a + [f"{self.orientation}.l{i}" for i in range(4)] + m


@dataclass(frozen=True)
class OutputMap:
    """A compiled output: kind (one of KINDS), nodal-coordinate indices dofs (k,),
    scale (reference length or divisor), element / mode index (mode outputs, else -1),
    direction (3,) (body-component outputs, else None)."""

    name: str
    kind: str
    dofs: np.ndarray
    scale: float
    element: int = -1
    mode: int = -1
    direction: np.ndarray | None = None

    def gradient(self, x: np.ndarray, Dx: np.ndarray | None = None) -> np.ndarray:
        """y_x on ``dofs`` (k,) at nodal coordinates x (n_x,); mode outputs need the
        element tensors Dx (ne, n_mode, n_dof) at x."""
        k = self.dofs.size
        if self.kind == "midpoint_deflection":
            grad = np.empty(6)
            midpoint_deflection(x[self.dofs], self.scale, grad)
            return grad
        if self.kind == "coordinate":
            return np.full(1, 1.0 / self.scale)
        if self.kind == "relative_rotation":
            return np.array([-1.0, 1.0])
        if self.kind == "body_component":
            grad = np.empty(10)
            body_component(x[self.dofs], self.direction, self.scale, grad)
            return grad
        return Dx[self.element, self.mode, :k] / self.scale
