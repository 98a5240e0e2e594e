"""Builder methods of :class:`periodyn.model.Model` for outputs chosen by the model:
any nodal coordinate, any deformation mode (in a spatial model also the rotation of a
hinge, e.g. a twist between two orientation nodes through a hinge whose rotation is
free), and the planar midpoint deflection and relative rotation."""

from __future__ import annotations

from ..errors import InputError
from .elements import MidpointDeflection
from .outputs import BodyComponent, CoordinateOutput, ModeOutput, RelativeRotation, check_scale
from .spatial import unit_axis


class OutputBuilder:
    """Mixin of Model: the output methods."""

    def add_midpoint_deflection(self, name: str, ends: tuple[str, str], mid: str, reference_length: float) -> None:
        """Output: distance of ``mid`` from the line through ``ends`` over reference_length
        (planar; in a spatial model use coordinate or mode outputs)."""
        self._require_dimension(2, "add_midpoint_deflection")
        for p in (*ends, mid):
            self._check_node(p, self.points, f"output '{name}'")
        if not reference_length > 0:
            raise InputError(f"output '{name}': reference_length must be positive, got {reference_length!r}")
        self._add_output(MidpointDeflection(name, tuple(ends), mid, float(reference_length)))

    def add_coordinate_output(self, name: str, coordinate: str, scale: float = 1.0) -> None:
        """Output: a nodal coordinate (``"<point>.x"``, an angle) divided by ``scale``."""
        self._check_coordinate(coordinate, f"output '{name}'")
        self._add_output(CoordinateOutput(name, coordinate, check_scale(name, scale)))

    def add_relative_rotation(self, name: str, angles: tuple[str, str]) -> None:
        """Output: rotation of angle node ``angles[1]`` relative to ``angles[0]`` (rad) (planar;
        in a spatial model add a hinge with a free rotation and :meth:`add_mode_output`)."""
        self._require_dimension(2, "add_relative_rotation")
        for a in angles:
            self._check_node(a, self.angles, f"output '{name}'")
        self._add_output(RelativeRotation(name, tuple(angles)))

    def add_mode_output(self, name: str, mode: str, scale: float = 1.0) -> None:
        """Output: a deformation mode ``"<element>.<mode>"`` divided by ``scale``."""
        if mode.count(".") != 1 or mode.split(".")[0] not in {e.name for e in self.elements}:
            raise InputError(f"output '{name}': '{mode}' is not a mode '<element>.<mode>' of an existing element")
        element, index = self._mode(mode)
        self._add_output(ModeOutput(name, mode, self.elements.index(element), index, tuple(element.coordinates()),
                                    check_scale(name, scale)))

    def add_body_component(self, name: str, points: tuple[str, str], orientation: str, direction,
                           scale: float = 1.0) -> None:
        """Output (spatial): ``direction . R^T (x_{points[1]} - x_{points[0]}) / scale`` with R the
        rotation of ``orientation`` and direction (3,) in its body components (normalized),
        e.g. the lateral midpoint deflection of a shaft in the frame of a co-rotating end."""
        self._require_dimension(3, "add_body_component")
        for p in points:
            self._check_node(p, self.points, f"output '{name}'")
        self._check_node(orientation, self.orientations, f"output '{name}'")
        d = unit_axis(f"output '{name}'", direction)
        self._add_output(BodyComponent(name, tuple(points), orientation, tuple(d), check_scale(name, scale)))

    def _add_output(self, output) -> None:
        if any(o.name == output.name for o in self.outputs):
            raise InputError(f"output '{output.name}' is defined twice; output names must be unique")
        self.outputs.append(output)

