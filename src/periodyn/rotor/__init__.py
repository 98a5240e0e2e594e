"""Rotors on a straight shaft: elements (shaft, disks, bearings, seals, masses), the
linearized equations in the stationary and co-rotating frames, Campbell diagrams, forced
response (unbalance, gravity, Bode)."""

from .element_rotor import ElementRotor, spatial_rotor, spatial_rotor_model
from .diagram import BACKWARD, FORWARD, campbell, stability_threshold
from .files import load_rotor
from .elements import Bearing, Disk, PointMass, Seal, ShaftSection, shaft_element
from .model import Rotor, RotorEquations, RotorModel
from .response import (Unbalance, critical_speeds, static_deflection, synchronous_response, unbalance_load,
                       unbalance_response)

__all__ = ["Rotor", "RotorModel", "RotorEquations", "Bearing", "Seal", "Disk", "PointMass", "ShaftSection",
           "shaft_element", "campbell", "stability_threshold", "FORWARD", "BACKWARD", "load_rotor",
           "ElementRotor", "spatial_rotor", "spatial_rotor_model", "Unbalance", "unbalance_load", "unbalance_response",
           "synchronous_response", "static_deflection", "critical_speeds"]
