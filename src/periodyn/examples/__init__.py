"""Builders for the papers' examples; each returns a model ready for periodyn.sweep."""

from .cardan import cardan_shaft, cardan_shaft_nonlinear
from .chain import parametric_chain
from .dae_examples import duffing, inverted_pendulum, rod_pendulum, slider_chain_pendulum, slider_rod_pendulum
from .elliptic_pendulum import pendulum_from_elements
from .pendulum import pendulum, pendulum_nonlinear
from .rotor import rotor
from .slider_crank import slider_crank, slider_crank_nonlinear

__all__ = ["cardan_shaft", "cardan_shaft_nonlinear", "duffing", "inverted_pendulum", "parametric_chain", "pendulum", "pendulum_from_elements",
           "pendulum_nonlinear", "rod_pendulum", "rotor", "slider_chain_pendulum", "slider_crank",
           "slider_crank_nonlinear", "slider_rod_pendulum"]
