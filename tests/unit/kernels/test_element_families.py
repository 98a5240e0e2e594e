"""The "add an element family" recipe of periodyn.kernels, checked on the source: every
family id is dispatched, has a data class, and every dispatched kernel is tested.

Read statically (ast), so the check costs no compilation.
"""

import ast
from pathlib import Path

import periodyn
from periodyn.kernels.elements import layout
from periodyn.kernels.mechanism.constraint_system import (PLANAR_FAMILIES, ModelArrays, PlanarArrays, SpatialArrays,
                                                          arrays_class)

SRC = Path(periodyn.__file__).parent
KERNELS = SRC / "kernels"
TESTS = Path(__file__).parent


def _tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text(), filename=str(path))


def _family_ids() -> set[str]:
    tree = _tree(KERNELS / "elements" / "layout.py")
    return {t.id for node in tree.body if isinstance(node, ast.Assign)
            for t in node.targets if isinstance(t, ast.Name) and t.id.startswith("FAMILY_")}


def _dispatch(path: Path, function: str) -> dict[str, tuple[str, str]]:
    """{FAMILY_X: (module, kernel)} of the if/elif chain ``if <v> == FAMILY_X: module.kernel(...)``
    inside ``function`` of ``path`` (one chain per family set, ``planar_``/``spatial_``)."""
    found = {}
    for node in ast.walk(_tree(path)):
        if isinstance(node, ast.FunctionDef) and node.name == function:
            for branch in ast.walk(node):
                if (isinstance(branch, ast.If) and isinstance(branch.test, ast.Compare)
                        and isinstance(branch.test.comparators[0], ast.Name)
                        and branch.test.comparators[0].id.startswith("FAMILY_")):
                    call = branch.body[0].value
                    assert isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute), \
                        f"{path.name}:{branch.lineno}: a family branch calls one kernel, module.function(...)"
                    found[branch.test.comparators[0].id] = (call.func.value.id, call.func.attr)
    assert found, f"no family dispatch found in {path.name}:{function}"
    return found


def _kernels(module: str) -> set[str]:
    tree = _tree(KERNELS / "elements" / f"{module}.py")
    return {node.name for node in tree.body if isinstance(node, ast.FunctionDef)}


def _sets(path: Path, function: str) -> dict[str, tuple[str, str]]:
    """The planar and spatial dispatch chains of ``function`` in ``path``, which share no family."""
    planar, spatial = _dispatch(path, f"planar_{function}"), _dispatch(path, f"spatial_{function}")
    assert not set(planar) & set(spatial), f"{path.name}: a family in both the planar and the spatial {function}"
    return planar | spatial


MODES = _sets(KERNELS / "mechanism" / "constraint_system.py", "deformation")
INERTIA = _sets(KERNELS / "mechanism" / "assembly.py", "inertia")


def test_every_family_is_in_its_sets_class():
    """A family's arrays class (recipe step 3) follows its chain: planar ids make PlanarArrays."""
    planar = set(_dispatch(KERNELS / "mechanism" / "constraint_system.py", "planar_deformation"))
    planar |= set(_dispatch(KERNELS / "mechanism" / "assembly.py", "planar_inertia"))
    assert {getattr(layout, name) for name in planar} == PLANAR_FAMILIES


def test_the_arrays_class_follows_the_family_set():
    """Planar ids (or none) pick the planar dispatch, spatial ids the spatial one, a mix both."""
    spatial = sorted(getattr(layout, name) for name in _family_ids()
                     if getattr(layout, name) not in PLANAR_FAMILIES)
    assert arrays_class(sorted(PLANAR_FAMILIES)) is PlanarArrays and arrays_class([]) is PlanarArrays
    assert arrays_class(spatial) is SpatialArrays
    assert arrays_class([layout.FAMILY_PLANAR_BEAM, layout.FAMILY_SPATIAL_BEAM]) is ModelArrays
    assert PlanarArrays._fields == SpatialArrays._fields == ModelArrays._fields


def test_every_family_id_is_dispatched_once():
    ids = _family_ids()
    assert set(MODES) | set(INERTIA) == ids, "a FAMILY_ id without a dispatch branch (recipe step 3)"
    assert set(MODES) <= ids and set(INERTIA) <= ids


def test_every_family_module_with_inertia_has_its_branch():
    """A module that defines ``inertia`` is called by element_arrays, one with ``deformation``
    by the modes dispatch (a kernel written but never called is recipe step 3 forgotten)."""
    for dispatch, kernel in ((MODES, "deformation"), (INERTIA, "inertia")):
        called = {module for module, name in dispatch.values() if name == kernel}
        for path in (KERNELS / "elements").glob("*.py"):
            if kernel in _kernels(path.stem):
                assert path.stem in called, f"elements/{path.stem}.{kernel} is not dispatched"


def test_every_family_id_has_one_data_class():
    owners = {}
    for path in (SRC / "model").glob("*.py"):
        for node in ast.walk(_tree(path)):
            if isinstance(node, ast.ClassDef):
                for item in node.body:
                    if (isinstance(item, ast.Assign) and isinstance(item.targets[0], ast.Name)
                            and item.targets[0].id == "family" and isinstance(item.value, ast.Name)):
                        owners.setdefault(item.value.id, []).append(node.name)
    for family in _family_ids():
        assert len(owners.get(family, [])) == 1, f"{family}: data classes {owners.get(family)} (recipe step 4)"


def test_every_dispatched_kernel_is_tested_against_a_twin():
    """Each module.kernel named by a dispatch is called in a kernel test that also imports a twin."""
    tested = set()
    for path in TESTS.glob("test_*.py"):
        text = path.read_text()
        if "tests.twins" not in text:
            continue
        for module, kernel in list(MODES.values()) + list(INERTIA.values()):
            if f"{module}.{kernel}" in text:
                tested.add((module, kernel))
    missing = set(MODES.values()) | set(INERTIA.values())
    assert missing <= tested, f"kernels without a twin test (recipe step 5): {sorted(missing - tested)}"
