"""Builders for the papers' examples; each returns a model ready for :func:`periodyn.sweep`,
:func:`periodyn.continuation` or :func:`periodyn.campbell`. Each builder's module is
imported on first use, so ``periodyn.examples.rotor()`` loads the rotor modules only."""

from __future__ import annotations

import importlib

#: builder -> module that defines it
_BUILDERS = {
    "pendulum": "pendulum_equation", "pendulum_nonlinear": "pendulum_equation",
    "pendulum_from_elements": "elliptic_pendulum",
    "slider_crank": "slider_crank_rod", "slider_crank_nonlinear": "slider_crank_rod",
    "rotor": "rotor_table1",
    "cardan_shaft": "cardan", "cardan_shaft_nonlinear": "cardan",
    "duffing": "dae_examples", "rod_pendulum": "dae_examples", "inverted_pendulum": "dae_examples",
    "slider_rod_pendulum": "dae_examples", "slider_chain_pendulum": "dae_examples",
    "parametric_chain": "chain",
}
__all__ = sorted(_BUILDERS)


def __getattr__(name: str):
    if name not in _BUILDERS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_BUILDERS[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
