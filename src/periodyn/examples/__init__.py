"""Builders for the papers' examples; each returns a model ready for periodyn.sweep."""

from .pendulum import pendulum

__all__ = ["pendulum"]
