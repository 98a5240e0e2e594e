"""Imports: every module imports on its own in a fresh interpreter, the package's module
graph (every import statement, also those inside functions) has no cycle, and
``import periodyn`` / the command line's start load none of the heavy libraries."""

from __future__ import annotations

import ast
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


def test_every_module_imports_on_its_own_in_a_fresh_interpreter():
    names = [n for n in modules() if not n.endswith("__main__")]
    code = ("import subprocess, sys\n"
            "from concurrent.futures import ThreadPoolExecutor\n"
            "def run(name):\n"
            "    r = subprocess.run([sys.executable, '-c', 'import ' + name], capture_output=True, text=True)\n"
            "    return name, r.returncode, (r.stderr.strip().splitlines() or [''])[-1]\n"
            "with ThreadPoolExecutor(2) as pool:\n"
            "    for name, code, last in pool.map(run, sys.argv[1:]):\n"
            "        if code: print(name, '->', last)\n")
    run = subprocess.run([sys.executable, "-c", code, *names], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "", run.stdout


@pytest.mark.parametrize("code", ["import periodyn", "import periodyn.cli; periodyn.cli.build_parser()"])
def test_light_start_loads_no_heavy_library(code):
    check = (f"{code}\nimport sys\n"
             f"print(' '.join(m for m in {HEAVY!r} if m in sys.modules))")
    run = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == ""


def test_public_names_resolve_lazily():
    for name in periodyn.__all__:
        assert getattr(periodyn, name) is not None
    assert periodyn.sweep.__module__ == "periodyn.sweep"
    with pytest.raises(AttributeError, match="no attribute 'nonexistent'"):
        periodyn.nonexistent


def test_importing_a_submodule_keeps_the_function_of_its_name():
    """periodyn.sweep / .transient / .continuation stay the functions after their modules
    are imported (as they were when __init__ imported everything)."""
    code = ("import periodyn.sweep, periodyn.transient, periodyn.continuation, sys, types\n"
            "import periodyn\n"
            "for name in ('sweep', 'transient', 'continuation'):\n"
            "    assert callable(getattr(periodyn, name)), name\n"
            "    assert isinstance(sys.modules['periodyn.' + name], types.ModuleType)\n"
            "from periodyn.sweep import sweep_file\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
