"""Imports: every module imports on its own (no cycle, every imported name bound where it
is looked for, every top level runs in a fresh interpreter), the package's
module graph (every import statement, also those inside functions) has no cycle, and
``import periodyn`` / the command line's start load none of the heavy libraries."""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
from pathlib import Path

import pytest

import periodyn

PACKAGE = Path(periodyn.__file__).resolve().parent
HEAVY = ("numpy", "scipy", "numba", "pyfftw", "xarray", "matplotlib", "dask", "h5netcdf")


def modules() -> dict[str, Path]:
    """Dotted name -> file of every module of the package."""
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


def imported(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """Package modules that ``name`` imports anywhere in its source."""
    out = set()
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            subs = [f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in known]
            out.update(subs)
            if len(subs) < len(node.names):
                out.add(base)
    return {m for m in out if m in known and m != name}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_cycle_finder_finds_a_known_cycle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert cycles(graph) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_module_graph_has_no_cycle():
    known = modules()
    graph = {name: imported(name, path, known) for name, path in known.items()}
    found = cycles(graph)
    detail = "; ".join(" <-> ".join(c) + " (" + ", ".join(f"{m} imports {sorted(graph[m] & set(c))}" for m in c) + ")"
                       for c in found)
    assert not found, f"import cycles: {detail}"


def defined_names(path: Path) -> set[str] | None:
    """Names bound at the top level of a module's source, or None when it defines
    ``__getattr__`` or calls ``lazy_package`` (a lazy package: its names exist only when
    asked for, and the one interpreter importing everything checks them)."""
    names = set()
    tree = ast.parse(path.read_text())
    if any(isinstance(n, ast.Call) and getattr(n.func, "id", None) == "lazy_package" for n in ast.walk(tree)):
        return None
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            if node.name == "__getattr__":
                return None
            names.add(node.name)
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names.update(n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name))
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names.update((a.asname or a.name).split(".")[0] for a in node.names)
        elif isinstance(node, (ast.If, ast.Try)):     # names bound on either branch
            names.update(n.name for n in ast.walk(node) if isinstance(n, (ast.FunctionDef, ast.ClassDef)))
            names.update(n.id for n in ast.walk(node) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store))
            names.update((a.asname or a.name).split(".")[0] for n in ast.walk(node)
                         if isinstance(n, (ast.Import, ast.ImportFrom)) for a in n.names)
    return names


def unresolved_imports(known: dict[str, Path]) -> list[str]:
    """``from <package module> import name`` statements (top level or inside
    functions) whose name is neither a submodule nor bound at the top level of that
    module: an import that works only after something else imported it."""
    defined = {name: defined_names(path) for name, path in known.items()}
    bad = []
    for name, path in known.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.ImportFrom):
                continue
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            if base not in known or defined[base] is None:
                continue
            for alias in node.names:
                if alias.name != "*" and alias.name not in defined[base] and f"{base}.{alias.name}" not in known:
                    bad.append(f"{name} (line {node.lineno}): {base} has no {alias.name!r}")
    return bad


def test_the_resolver_finds_a_missing_name(tmp_path):
    package = tmp_path / "pkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "a.py").write_text("def f():\n    pass\nif True:\n    g = 1\n")
    (package / "b.py").write_text("from .a import f, g\n\ndef h():\n    from .a import missing\n")
    known = {"pkg": package / "__init__.py", "pkg.a": package / "a.py", "pkg.b": package / "b.py"}
    assert unresolved_imports(known) == ["pkg.b (line 4): pkg.a has no 'missing'"]


def test_every_module_imports_on_its_own():
    """A module imports on its own when the graph has no cycle (above), every name it
    imports from the package is bound where it is looked for (checked statically, also
    for imports inside functions), and its top level runs: two fresh interpreters import
    every module, in sorted order (each package before its modules) and in reverse."""
    known = modules()
    assert not unresolved_imports(known), "\n".join(unresolved_imports(known))
    names = [n for n in known if not n.endswith("__main__")]
    every = "import importlib, sys\nfor name in sys.argv[1:]:\n    importlib.import_module(name)\n"
    runs = [subprocess.Popen([sys.executable, "-c", every, *order], stderr=subprocess.PIPE, text=True)
            for order in (names, names[::-1])]
    for run in runs:
        _, err = run.communicate(timeout=300)
        assert run.returncode == 0, err


@pytest.mark.parametrize("code", ["import periodyn", "import periodyn.cli; periodyn.cli.build_parser()"])
def test_light_start_loads_no_heavy_library(code):
    check = (f"{code}\nimport sys\n"
             f"print(' '.join(m for m in {HEAVY!r} if m in sys.modules))")
    run = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == ""


#: the package's layers in the order of the data flow: a module imports only from its own
#: layer or below (DESIGN.md, "Target layout"); ``periodyn/__init__`` (the lazy front of the
#: public names) and ``_moved`` (old import paths) stand outside
LAYERS = (("errors", "kernels"), ("numerics",), ("system", "dae", "periodic", "results"), ("model",), ("harmonic",),
          ("stability",), ("nonlinear",), ("averaging", "speeds", "rotor"), ("arclength",), ("examples",),
          ("engine",), ("studies",), ("plotting",), ("cli",))
OUTSIDE = ("periodyn", "periodyn._moved")


def layer(name: str) -> int:
    top = name.split(".")[1]
    return next(i for i, tops in enumerate(LAYERS) if top in tops)


def test_every_module_has_a_layer_and_nothing_imports_upward():
    known = modules()
    unplaced = [n for n in known if n not in OUTSIDE and not any(n.split(".")[1] in tops for tops in LAYERS)]
    assert not unplaced, f"modules outside every layer (add them to LAYERS and DESIGN.md): {unplaced}"
    upward = [f"{n} (layer {layer(n)}) imports {t} (layer {layer(t)})"
              for n, path in known.items() if n not in OUTSIDE
              for t in sorted(imported(n, path, known)) if t not in OUTSIDE and layer(t) > layer(n)]
    assert not upward, "\n".join(upward)


def test_no_module_shares_a_public_name_of_its_package_or_of_its_own_functions():
    """``import periodyn.x.y`` binds ``y`` on ``periodyn.x``: a submodule named like a
    function its package exports would replace that function, and a module named like its
    own function reads ambiguously (``periodyn.continuation`` was both)."""
    known = modules()
    clashes = []
    for name, path in known.items():
        leaf = name.rpartition(".")[2]
        own = {n.name for n in ast.parse(path.read_text()).body
               if isinstance(n, (ast.FunctionDef, ast.ClassDef)) and not n.name.startswith("_")}
        if leaf in own:
            clashes.append(f"{name} defines {leaf}()")
    for package, path in known.items():
        if path.name != "__init__.py":
            continue
        exported = set(getattr(importlib.import_module(package), "__all__", ()))
        subs = {n.rpartition(".")[2] for n in known if n.rpartition(".")[0] == package}
        clashes += [f"{package} exports {n!r} and has a submodule of that name"
                    for n in sorted(exported & subs) if n not in getattr(importlib.import_module(package),
                                                                          "_SUBMODULES", ())]
    assert not clashes, "\n".join(clashes)


def test_public_names_resolve_lazily_and_stay_functions_after_their_modules_load():
    for name in periodyn.__all__:
        assert getattr(periodyn, name) is not None
    assert periodyn.sweep.__module__ == "periodyn.engine.front"
    with pytest.raises(AttributeError, match="no attribute 'nonexistent'"):
        periodyn.nonexistent
    code = ("import periodyn.engine.front, periodyn.averaging, periodyn.arclength, periodyn.rotor.diagram\n"
            "import periodyn, periodyn.rotor, periodyn.examples.rotor_table1\n"
            "for f in (periodyn.sweep, periodyn.transient, periodyn.continuation, periodyn.rotor.campbell,\n"
            "          periodyn.examples.rotor):\n"
            "    assert callable(f) and not isinstance(f, type(periodyn)), f\n"
            "from periodyn import ExecutionOptions, OutputOptions, ContinuationOptions\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr


def test_an_old_import_path_forwards_to_the_new_module_with_a_deprecation_warning():
    code = ("import warnings\n"
            "warnings.simplefilter('error', DeprecationWarning)\n"
            "try:\n"
            "    import periodyn.hill\n"
            "except DeprecationWarning as w:\n"
            "    assert 'periodyn.stability.hill' in str(w), w\n"
            "else:\n"
            "    raise SystemExit('no warning')\n"
            "warnings.simplefilter('ignore', DeprecationWarning)\n"
            "from periodyn.hill import characteristic_exponents\n"
            "from periodyn.stability.methods import characteristic_exponents as new\n"
            "assert characteristic_exponents is new\n"
            "from periodyn.config import ensure\n"
            "from periodyn.studies.spec import ensure as new_ensure\n"
            "assert ensure is new_ensure\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr + run.stdout
