"""Old import paths of modules that moved when the layout came to follow the data flow
(release 0.2): ``import periodyn.hill`` still works for one release, with a
DeprecationWarning naming the new path, through a module that forwards every attribute to
the module at its new place. Not kept: paths that are now the functions of those names
(``periodyn.sweep``, ``periodyn.transient``, ``periodyn.continuation``, ``periodyn.rotor.campbell``,
``periodyn.nonlinear.ihb``, ``periodyn.examples.pendulum``, ``.rotor``, ``.slider_crank``):
their modules are ``periodyn.engine.front``, ``periodyn.averaging``, the package
``periodyn.arclength``, ``periodyn.rotor.diagram``, ``periodyn.nonlinear.ihb_solver`` and
``periodyn.examples.pendulum_equation``, ``.rotor_table1``, ``.slider_crank_rod``."""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import types
import warnings

#: old module (below periodyn) -> its module now (a tuple: the modules its names went to,
#: looked up in order)
MOVED = {
    "_forkserver_preload": "engine._forkserver_preload",
    "analysis": "speeds",
    "boundaries": "stability.boundaries",
    "config": "studies.spec",
    "config_checks": "studies.checks",
    "config_elements": "studies.elements",
    "floquet": "stability.floquet",
    "harmonic.batch": "harmonic.batch_balance",
    "hb": "harmonic.balance",
    "hill": ("stability.hill", "stability.methods"),
    "kernels.assembly": "kernels.mechanism.assembly",
    "kernels.banded": "kernels.solvers.banded",
    "kernels.constraints": "kernels.mechanism.constraint_system",
    "kernels.elastic": "kernels.elements.elastic",
    "kernels.floquet": "kernels.solvers.floquet",
    "kernels.harmonic": "kernels.solvers.harmonic",
    "kernels.implicit": "kernels.solvers.implicit",
    "kernels.jets": "kernels.elements.jets",
    "kernels.layout": "kernels.elements.layout",
    "kernels.lu": "kernels.mechanism.lu",
    "kernels.magnus_ladder": "kernels.solvers.magnus_ladder",
    "kernels.nonlinear": "kernels.mechanism.equations",
    "kernels.ode_flow": "kernels.solvers.ode_flow",
    "kernels.outputs": "kernels.mechanism.outputs",
    "kernels.planar_beam": "kernels.elements.planar_beam",
    "kernels.planar_geometry": "kernels.elements.planar_geometry",
    "kernels.planar_hinge": "kernels.elements.planar_hinge",
    "kernels.planar_truss": "kernels.elements.planar_truss",
    "kernels.rigid2d": "kernels.solvers.rigid2d",
    "kernels.rigid2d_flow": "kernels.solvers.rigid2d_flow",
    "kernels.rigid_body": "kernels.elements.rigid_body",
    "kernels.rotation": "kernels.elements.rotation",
    "kernels.saddle": "kernels.solvers.saddle",
    "kernels.spatial_beam": "kernels.elements.spatial_beam",
    "kernels.spatial_joints": "kernels.elements.spatial_joints",
    "kernels.spatial_truss": "kernels.elements.spatial_truss",
    "kernels.split": "kernels.mechanism.split",
    "kernels.transfer": "kernels.mechanism.transfer",
    "kernels.vector_inertia": "kernels.elements.vector_inertia",
    "kinematics": "model.kinematics",
    "linearize": "model.linearization",
    "magnus": "stability.magnus",
    "nonlinear.chord": "nonlinear.jacobian_reuse",
    "nonlinear.integrate": "numerics.integration",
    "nonlinear.krylov": "numerics.krylov",
    "nonlinear.linear": "dae",
    "nonlinear.newton": "numerics.newton_iteration",
    "nonlinear.problem": "dae",
    "nonlinear.stiff": "numerics.stiff",
    "nonlinear.variational": "numerics.variational",
    "progress": "engine.progress",
    "spectra": "numerics.spectra",
    "study": "studies.continuation",
    "study_points": "studies.points",
    "timedomain": "stability.monodromy",
    "transient_study": "studies.transient",
}


class _Forward(importlib.abc.Loader):
    def __init__(self, new: tuple[str, ...]):
        self.new = new

    def create_module(self, spec):
        return None

    def exec_module(self, module: types.ModuleType) -> None:
        targets = [importlib.import_module(name) for name in self.new]

        def forward(name):
            for target in targets:
                if hasattr(target, name):
                    return getattr(target, name)
            return getattr(targets[0], name)

        module.__getattr__ = forward
        module.__dir__ = lambda: sorted(set().union(*map(dir, targets)))
        module.__doc__ = f"Moved to {', '.join(self.new)} (this path is deprecated)."


class MovedModules(importlib.abc.MetaPathFinder):
    """Finds ``periodyn.<old>`` for every old path in :data:`MOVED`."""

    def find_spec(self, fullname, path=None, target=None):
        old = fullname.partition("periodyn.")[2] if fullname.startswith("periodyn.") else None
        if old not in MOVED:
            return None
        moved = MOVED[old] if isinstance(MOVED[old], tuple) else (MOVED[old],)
        new = tuple(f"periodyn.{name}" for name in moved)
        warnings.warn(f"{fullname} moved to {' and '.join(new)}; the old path goes in the next release",
                      DeprecationWarning, stacklevel=3)
        return importlib.util.spec_from_loader(fullname, _Forward(new))


def install() -> None:
    """Put the finder on ``sys.meta_path`` once (after the normal finders)."""
    if not any(isinstance(f, MovedModules) for f in sys.meta_path):
        sys.meta_path.append(MovedModules())
