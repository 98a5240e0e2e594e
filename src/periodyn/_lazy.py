"""Packages whose public names are imported on first use (module ``__getattr__``).

A function may share its name with the submodule that defines it (``periodyn.sweep``,
``periodyn.nonlinear.ihb``): importing that submodule must not replace the package's
function by the module, so the package module gets a class that refuses exactly that
assignment; the submodule stays reachable as ``sys.modules["<package>.<name>"]``.
"""

from __future__ import annotations

import importlib
import sys
import types


def lazy_package(package: str, names: dict[str, str], submodules: tuple[str, ...] = ()) -> list[str]:
    """Make ``package`` import ``names`` (public name -> submodule defining it) and
    ``submodules`` on first attribute access; returns the sorted ``__all__``."""
    module = sys.modules[package]
    public = sorted([*names, *submodules])

    def __getattr__(name: str):
        if name in names:
            value = getattr(importlib.import_module(f".{names[name]}", package), name)
        elif name in submodules:
            value = importlib.import_module(f".{name}", package)
        else:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        setattr(module, name, value)  # later look-ups skip this function
        return value

    def __dir__() -> list[str]:
        return sorted([*vars(module), *public])

    class LazyPackage(types.ModuleType):
        def __setattr__(self, name: str, value) -> None:
            if names.get(name) == name and isinstance(value, types.ModuleType):
                return
            super().__setattr__(name, value)

    module.__getattr__ = __getattr__
    module.__dir__ = __dir__
    module.__class__ = LazyPackage
    return public
