"""Builders for the papers' examples; each returns a model ready for periodyn.sweep."""

from .chain import parametric_chain
from .elliptic_pendulum import pendulum_from_elements
from .pendulum import pendulum
from .slider_crank import slider_crank

__all__ = ["parametric_chain", "pendulum", "pendulum_from_elements", "slider_crank"]
