"""Model description (planar and spatial): nodes, element families as data, masses, loads,
inputs, outputs; and the planar rigid-body builder of DAE models (``rigid2d.PlanarSystem``)."""

from .driving import AngleFunction
from .elements import (FLEXIBLE, FREE, RIGID, IndependentElement, MidpointDeflection, PlanarBeam,
                       PlanarHinge, PlanarTruss)
from .model import CompiledModel, Model
from .rigid2d import PlanarSystem
from .outputs import CoordinateOutput, ModeOutput, OutputMap, RelativeRotation
from .spatial import EulerNormalization, RigidBody, RigidLink, SpatialHinge, SpatialTruss
from .spatial_beam import BeamSection, SpatialBeam

__all__ = ["Model", "CompiledModel", "AngleFunction", "PlanarBeam", "PlanarTruss", "PlanarHinge", "MidpointDeflection",
           "IndependentElement", "RIGID", "FLEXIBLE", "FREE",
           "CoordinateOutput", "RelativeRotation", "ModeOutput", "OutputMap",
           "EulerNormalization", "SpatialTruss", "SpatialHinge", "RigidLink", "RigidBody", "BeamSection",
           "SpatialBeam", "PlanarSystem"]
