"""Command line: ``periodyn sweep | serve | figures | bench | warmup | info`` (see ``periodyn --help``).

Exit codes: 0 success, 1 a computation or figure script failed, 2 bad input or an OS error
(a message naming the problem, the path and the fix, never a traceback), 130 interrupted.
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

from .engine.server import IDLE_S, SERVER_ENV
from .engine.session import caused_by_interrupt
from .engine.threads import AUTO_PARALLEL_POINTS, WORKER_THREAD_ENV, available_cores
from .errors import ConvergenceError, InputError

# Heavy modules (numpy, numba, pyfftw, xarray, matplotlib, the solvers) are imported by the
# commands that use them, so `periodyn --help` starts in a fraction of a second.

__all__ = ["main", "build_parser"]

_EPILOG = """examples:
  periodyn sweep sweeps/pendulum.toml --plot results/pendulum.png
  periodyn sweep sweeps/pendulum.toml --omega 0.5:0.6:2000 --workers 2 --out results/zoom.nc
  periodyn sweep sweeps/pendulum.toml --resume          # continue an interrupted sweep
  periodyn sweep sweeps/dae_rod_pendulum.toml --plot results/rod.png   # a continuation study
  periodyn sweep sweeps/slider_crank_transient.toml     # a transient from rest at one speed
  periodyn sweep sweeps/rotor_campbell.toml --plot results/campbell.png   # a rotor's Campbell diagram
  periodyn sweep sweeps/cardan_chart.toml --plot results/chart.png   # stability boundaries over a parameter
  periodyn figures                                      # every figure into figures/png/
  periodyn bench sweep
  periodyn warmup                                       # compile the kernels once after install
  periodyn serve start                                  # keep a warm process: later sweeps start at once
  periodyn info
"""


def _omega_range(text: str) -> tuple[float, float, int]:
    parts = text.split(":")
    try:
        if len(parts) != 3:
            raise ValueError
        start, stop, num = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise argparse.ArgumentTypeError(f"--omega takes start:stop:num (e.g. 0.1:1.4:500), got {text!r}") from None
    if not (start > 0 and stop > 0 and num >= 1):
        raise argparse.ArgumentTypeError(f"--omega needs start > 0, stop > 0 and num >= 1, got {text!r}")
    return start, stop, num


def _workers(text: str) -> int | str:
    if text == "auto":
        return text
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--workers takes a number of processes or 'auto', got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"--workers must be >= 0 (0 = all cores), got {value}")
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="periodyn", formatter_class=argparse.RawDescriptionHelpFormatter, epilog=_EPILOG,
        description="Periodic vibrations, transients and stability of driven mechanisms and rotors "
                    "over large speed sweeps.")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    sw = commands.add_parser("sweep", help="run a sweep file and write its results (and a figure)",
                             description="Run the sweep described by a TOML sweep file (see sweeps/*.toml and "
                                         "periodyn.studies.spec) and write one netCDF result file.")
    sw.add_argument("file", type=Path, help="study file: a speed sweep ([sweep] table), e.g. sweeps/pendulum.toml, "
                                            "a continuation study ([continuation]), e.g. sweeps/dae_rod_pendulum.toml, "
                                            "a transient ([transient]), e.g. sweeps/slider_crank_transient.toml, or "
                                            "a Campbell diagram ([campbell]), e.g. sweeps/rotor_campbell.toml, or a stability "
                                            "chart ([chart]), e.g. sweeps/cardan_chart.toml")
    sw.add_argument("--omega", type=_omega_range, metavar="START:STOP:NUM",
                    help="replace the file's speeds by NUM speeds from START to STOP, in the file's omega unit "
                         "(a continuation study takes START:STOP as its range and ignores NUM; a Campbell "
                         "study's speeds)")
    sw.add_argument("--out", type=Path, metavar="FILE", help="result file (default results/<name>.nc)")
    sw.add_argument("--plot", type=Path, metavar="FILE",
                    help="also draw the result: amplitude per output (unstable points marked) and max Re "
                         "exponent, branches, time history or Campbell diagram")
    sw.add_argument("--resume", action="store_true",
                    help="continue an interrupted sweep of the same file and --out, computing only missing points; "
                         "a finished result of the same request is read, one made otherwise refused")
    sw.add_argument("--workers", type=_workers, default="auto", metavar="N",
                    help="worker processes; 0 = all cores; 'auto' (default): all cores for sweeps of "
                         f"{AUTO_PARALLEL_POINTS}+ points, else 1; with --scheduler local: Dask workers")
    sw.add_argument("--scheduler", metavar="ADDR",
                    help="run on a Dask cluster: its scheduler address (tcp://host:8786), or 'local' to start "
                         "a local Dask cluster of --workers processes")
    sw.add_argument("--chunk-size", type=int, metavar="N",
                    help="points per chunk (checkpoint granularity); default: up to 128, 8+ chunks per worker")
    sw.add_argument("--quiet", "-q", action="store_true", help="no progress output and no summary")

    fg = commands.add_parser("figures", help="regenerate figures from figures/fig*.py",
                             description="Run the figure scripts figures/fig*.py (each has "
                                         "main(out_dir) -> list of paths); missing sweep results are computed.")
    fg.add_argument("names", nargs="*", metavar="NAME", help="scripts to run, by name or prefix (default: all)")
    fg.add_argument("--out-dir", type=Path, metavar="DIR", help="output folder (default figures/png/)")
    fg.add_argument("--list", action="store_true", help="list the figure scripts and exit")

    bn = commands.add_parser("bench", help="run benchmarks/bench_*.py",
                             description="Run the benchmark scripts benchmarks/bench_*.py, each in its own "
                                         "process; they print their measurements.")
    bn.add_argument("names", nargs="*", metavar="NAME", help="benchmarks, e.g. 'sweep' for bench_sweep.py "
                                                              "(default: all)")
    bn.add_argument("--list", action="store_true", help="list the benchmarks and exit")

    sv = commands.add_parser(
        "serve", help="keep a warm server that runs later `periodyn sweep` commands (start | stop | status | run)",
        description="A server process that has imported periodyn and loaded the compiled kernels of the speed "
                    "solver, of the files named here and of every sweep it has run, so that a later `periodyn "
                    "sweep` skips seconds of imports and kernel loading, and its workers start with the kernels "
                    "(periodyn.engine.server). While it runs, `periodyn sweep` commands run in it, with the "
                    f"terminal, folder and environment of the caller; set {SERVER_ENV}=off to run one here.")
    sv.add_argument("action", choices=("start", "stop", "status", "run"),
                    help="start it in the background, stop it, say whether it runs, or run it in this terminal")
    sv.add_argument("files", nargs="*", type=Path, metavar="FILE",
                    help="sweep files whose kernels to load at the start (the rest are loaded after their first sweep)")
    sv.add_argument("--idle", type=float, default=IDLE_S / 60, metavar="MIN",
                    help=f"stop after MIN minutes without a command (default {IDLE_S / 60:g})")

    commands.add_parser("warmup", help="compile the numerical kernels into Numba's cache (once per install)",
                        description="Compile (or load) every kernel family once, one progress line per step, so "
                                    "that the first sweep and its worker processes start from a warm cache.")
    commands.add_parser("info", help="versions, cores, threads, BLAS and FFTW",
                        description="Print package versions, CPU cores, thread settings, BLAS and FFTW details.")
    return parser


# ----------------------------------------------------------------------------- sweep
def _summary(ds, out: Path, elapsed: float) -> list[str]:
    from .plotting import speed_axis, unstable_spans

    points = int(ds.attrs["points"])
    computed = int(ds.attrs.get("points_computed", points))
    restored = f", {points - computed} restored from checkpoints" if computed < points else ""
    lines = [f"{ds.attrs['model']}: {points} points{restored}, {ds.attrs['failed_points']} failed, {elapsed:.1f} s "
             f"({computed / max(elapsed, 1e-9):.0f} points/s computed); wrote {out}"]
    if ds["stable"].ndim == 1 and int(ds.attrs.get("stability", 1)):
        x, label = speed_axis(ds)
        spans = unstable_spans(x, ds["stable"].values)
        text = ", ".join(f"[{a:.4g}, {b:.4g}]" for a, b in spans) or "none"
        lines.append(f"unstable (or failed) points, {label}: {text}")
    return lines


def _cmd_sweep(args) -> int:
    from .engine.session import check_output
    from .engine.warmup import announce_compiles
    from .studies.spec import load_sweep_file

    announce_compiles(None if args.quiet else sys.stderr)  # building the model may compile kernels too
    spec = load_sweep_file(args.file)
    out = args.out or Path("results") / f"{spec.name}.nc"
    check_output(out)  # before any computing
    if args.plot:
        check_output(args.plot, "--plot")
    description = " ".join(spec.description.split())
    title = f"{spec.name}: {description}" if description else spec.name
    kind = {"sweep": _cmd_speed_sweep, "continuation": _cmd_study, "transient": _cmd_transient,
            "campbell": _cmd_campbell, "chart": _cmd_chart}[spec.kind]
    lines, figure = kind(args, spec, out, title)
    if args.plot:
        from .plotting import save_figure

        save_figure(figure(), args.plot)
    if not args.quiet:
        print("\n".join(lines + ([f"figure: {args.plot}"] if args.plot else [])))
    return 0


def _run(spec, out: Path, **options):
    """(result, seconds) of the study ``spec`` run into ``out``."""
    from .studies.spec import run

    start = time.perf_counter()
    result = run(spec, out, **options)
    return result, time.perf_counter() - start


def _one_process(args, spec, what: str, omega: bool = True) -> None:
    """Refuse the options of a sweep that a study run in one process does not take."""
    if args.scheduler or args.chunk_size or (args.omega and not omega):
        flags = ("" if omega else "--omega, ") + "--scheduler and --chunk-size"
        raise InputError(f"{spec.source} is {what}, run in one process; drop {flags}")


def _cmd_speed_sweep(args, spec, out: Path, title: str):
    from .plotting import plot_sweep

    workers = args.workers
    if workers == "auto" and args.scheduler:
        workers = available_cores()
    speeds = spec.omega_values(args.omega)
    if len(speeds) > 1 and speeds[0] > speeds[-1] and not args.quiet:
        print(f"note: the speeds run down, from {speeds[0]:g} to {speeds[-1]:g} {spec.omega_unit}; the results "
              "keep that descending order", file=sys.stderr)
    ds, elapsed = _run(spec, out, omega=args.omega, workers=workers, scheduler=args.scheduler, resume=args.resume,
                       progress=False if args.quiet else None, chunk_size=args.chunk_size)
    lines = _summary(ds, out, elapsed)
    if "boundary_omega" in ds:
        found = zip(ds["boundary_omega"].values, ds["boundary_kind"].values, ds["boundary_becomes_stable"].values)
        lines.append("stability boundaries (rad/s): " + (", ".join(
            f"{w:.8g} {k} ({'stable' if up else 'unstable'} above)" for w, k, up in found) or "none"))
    return lines, lambda: plot_sweep(ds, title=title)


def _cmd_study(args, spec, out: Path, title: str):
    from .plotting import plot_study

    _one_process(args, spec, "a continuation study")
    if args.omega and not args.quiet and spec.speeds is not None:
        print(f"note: --omega replaces the study's given speeds by {args.omega[2]} speeds from {args.omega[0]:g} "
              f"to {args.omega[1]:g} {spec.omega_unit}", file=sys.stderr)
    elif args.omega and not args.quiet:
        print(f"note: a continuation study follows omega from {args.omega[0]:g} to {args.omega[1]:g} "
              f"{spec.omega_unit} with its own steps; NUM ({args.omega[2]}) is ignored", file=sys.stderr)
    branches, elapsed = _run(spec, out, omega=args.omega, resume=args.resume,
                             progress=None if args.quiet else sys.stderr)
    lines = []
    for key, branch in branches.items():
        kinds = [sp.type for sp in branch.special_points]
        special = ", ".join(f"{kinds.count(k)} {k}" for k in dict.fromkeys(kinds)) or "no special points"
        lines.append(f"{spec.name} {key}: {len(branch)} points, {special}")
    if spec.period_doubling is not None and "period_doubled" not in branches:
        lines.append("note: no period-doubling point on the frequency branch, so no period_doubled branch")
    lines.append(f"{spec.example}: {len(branches)} branches, {elapsed:.1f} s; wrote {out}")
    return lines, lambda: plot_study(branches, title)


def _cmd_transient(args, spec, out: Path, title: str):
    from .plotting import plot_transient

    _one_process(args, spec, "a transient study at one speed", omega=False)
    ds, elapsed = _run(spec, out, resume=args.resume)
    return [f"{spec.example}: transient at omega = {spec.omega:g} rad/s, {ds.sizes['time']} times, methods "
            f"{', '.join(map(str, ds['method'].values))}, {elapsed:.1f} s; wrote {out}"], \
        lambda: plot_transient(ds, title)


def _cmd_campbell(args, spec, out: Path, title: str):
    from .plotting import plot_campbell
    from .studies.campbell import campbell_summary, unbalance_result

    _one_process(args, spec, "a Campbell study")
    if args.plot and spec.grid:
        raise InputError(f"{spec.source}: --plot draws one rotor, but this study has a [campbell.grid] "
                         f"({', '.join(spec.grid)}); drop --plot and draw a grid point from the result file")
    ds, elapsed = _run(spec, out, omega=args.omega, resume=args.resume)
    response = unbalance_result(out)
    grid = "".join(f" x {len(v)} {k}" for k, v in spec.grid.items())
    return [f"{spec.example}: Campbell diagram, {ds.sizes['speed']} speeds x {ds.sizes['mode']} modes{grid}, "
            f"{campbell_summary(ds, response)}, {elapsed:.1f} s; wrote {out}"], \
        lambda: plot_campbell(ds, title, unbalance=response)


def _cmd_chart(args, spec, out: Path, title: str):
    from .plotting import plot_stability_chart
    from .studies.chart import chart_summary

    _one_process(args, spec, "a stability chart", omega=False)
    ds, elapsed = _run(spec, out, resume=args.resume)
    return [f"{spec.example}: stability chart over {spec.parameter_name}, {ds.sizes['boundary']} boundaries, "
            f"{ds.attrs['evaluations']} exponent evaluations, {ds.attrs['builds']} models, {elapsed:.1f} s; "
            f"wrote {out}", *chart_summary(ds)], lambda: plot_stability_chart(ds, title)


# ----------------------------------------------------------------------------- scripts
def _chosen_scripts(args, folder: str, pattern: str, prefix: str, what: str) -> tuple[Path, list[Path]]:
    """(project root, the scripts ``args.names`` choose in ``<root>/<folder>``), or (root, [])
    after printing their names when ``args.list`` is set or there are none."""
    from .studies.spec import project_root

    root = project_root()
    scripts = _scripts(root / folder, pattern, prefix, args.names)
    if args.list or not scripts:
        print("\n".join(p.stem for p in scripts) or f"no {what} in {root / folder}")
        return root, []
    return root, scripts


def _scripts(folder: Path, pattern: str, prefix: str, names: list[str]) -> list[Path]:
    found = sorted(folder.glob(pattern))
    if not names:
        return found
    chosen = []
    for name in names:
        matches = [p for p in found if p.stem == name or p.stem == prefix + name
                   or p.stem.startswith(name) or p.stem.startswith(prefix + name)]
        if not matches:
            known = ", ".join(p.stem for p in found) or f"none in {folder}"
            raise InputError(f"no script matches '{name}'; available: {known}")
        chosen.extend(m for m in matches if m not in chosen)
    return chosen


def _cmd_figures(args) -> int:
    import importlib.util

    root, scripts = _chosen_scripts(args, "figures", "fig*.py", "fig", "figure scripts")
    if not scripts:
        return 0
    out_dir = args.out_dir.resolve() if args.out_dir else root / "figures" / "png"
    failed = []
    previous = Path.cwd()
    os.chdir(root)  # scripts find sweeps/ and results/ from the project root
    try:
        for i, script in enumerate(scripts, 1):
            start = time.perf_counter()
            print(f"[{i}/{len(scripts)}] {script.stem} ...", flush=True)
            try:
                spec = importlib.util.spec_from_file_location(f"periodyn_figure_{script.stem}", script)
                module = importlib.util.module_from_spec(spec)
                spec.loader.exec_module(module)
                paths = module.main(out_dir)
            except Exception as exc:  # one broken script must not stop the others
                failed.append(script.stem)
                print(f"{script.stem}: FAILED ({type(exc).__name__}: {exc})", file=sys.stderr)
                continue
            print(f"[{i}/{len(scripts)}] {script.stem} ({time.perf_counter() - start:.1f} s): "
                  + ", ".join(str(p) for p in paths), flush=True)
    finally:
        os.chdir(previous)
    if failed:
        print(f"{len(failed)} of {len(scripts)} figure scripts failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


def _cmd_bench(args) -> int:
    root, scripts = _chosen_scripts(args, "benchmarks", "bench_*.py", "bench_", "benchmarks")
    if not scripts:
        return 0
    status = 0
    for script in scripts:
        print(f"== {script.stem}", flush=True)
        status = max(status, subprocess.call([sys.executable, str(script)], cwd=root))
    return 1 if status else 0


def _cmd_serve(args) -> int:
    from .engine import server

    if args.action == "status":
        state = server.ping()
        if state is None:
            print(f"no periodyn server runs for this code and environment ({server.socket_path()})")
            return 1
        print(f"periodyn server: pid {state['pid']}, socket {server.socket_path()}, {state['running']} command(s) "
              f"running, kernels of: {', '.join(state['learned']) or 'the speed solver only'}")
        return 0
    if args.action == "stop":
        print("periodyn server stopped" if server.stop() else "no periodyn server runs for this code and environment")
        return 0
    files = [str(f.resolve()) for f in args.files]
    for file in files:
        if not Path(file).is_file():
            raise InputError(f"{file} is not a sweep file; give existing files (or none)")
    if args.idle <= 0:
        raise InputError(f"--idle must be a positive number of minutes, got {args.idle}")
    if args.action == "run":
        return server.serve(main, _learn, idle=args.idle * 60, preload=lambda: _preload(files),
                            ready=lambda path: print(f"periodyn server: serving at {path}", flush=True))
    return _start_server(files, args.idle)


def _start_server(files: list[str], idle: float) -> int:
    """``periodyn serve start``: the server in a background process of its own session,
    its output into a log beside its socket; returns once it answers."""
    from .engine import server

    state = server.ping()
    if state is not None:
        print(f"a periodyn server already runs (pid {state['pid']}); `periodyn serve stop` stops it")
        return 0
    path = server.socket_path()
    path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
    log = path.with_suffix(".log")
    command = [sys.executable, "-m", "periodyn.cli", "serve", "run", *files, "--idle", str(idle)]
    with open(log, "w") as out:
        process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.STDOUT,
                                   start_new_session=True)
    print("periodyn server: starting (importing, loading the kernels; compiling them where Numba's cache is "
          "empty, see `periodyn warmup`)", flush=True)
    while process.poll() is None:
        state = server.ping()
        if state is not None:
            print(f"periodyn server: up (pid {state['pid']}); `periodyn sweep` commands run in it until `periodyn "
                  f"serve stop` or {idle:g} min without one (log: {log})")
            return 0
        time.sleep(0.2)
    print(f"periodyn serve: error: the server ended at its start (exit {process.returncode}); its log {log}:\n"
          + log.read_text()[-3000:], file=sys.stderr)
    return 1


def _preload(files: list[str]) -> set[str]:
    """The server's start: the speed solver's kernels, and those of ``files``; returns
    the families of ``files``."""
    from .speeds import warm_up

    warm_up()
    learned: set[str] = set()
    for file in files:
        family = _learn(["sweep", file], learned)
        if family:
            learned.add(family)
    return learned


def _learn(argv: list[str], learned: set[str]) -> str | None:
    """Load into this process (the server) the kernels that the command ``argv`` runs,
    unless its family is in ``learned``: for a speed sweep, its model built past the
    model cache and two of its speeds solved and written (which imports the result
    writer). Returns the family (the file's example or name), or None for other commands."""
    try:
        args = build_parser().parse_args(argv)
    except SystemExit:
        return None
    if args.command != "sweep":
        return None
    from unittest import mock

    from .engine.front import sweep
    from .studies.spec import load_sweep_file

    spec = load_sweep_file(args.file)
    family = spec.example or spec.name
    if spec.kind != "sweep" or family in learned:
        return None
    with mock.patch.dict(os.environ, {"PERIODYN_MODEL_CACHE": "off"}):  # the build itself loads the model's kernels
        plan = spec.plan(None)
    first = {name: values[:1] for name, values in plan.parameters.items()} if plan.parameters else None
    middle = plan.omega[len(plan.omega) // 2:][:2]
    with warnings.catch_warnings(), tempfile.TemporaryDirectory(prefix="periodyn-learn-") as folder:
        warnings.simplefilter("ignore")  # what these speeds find is not reported: the kernels are what counts
        sweep(plan.model, middle, spec.harmonics, spec.samples, spec.method if spec.stability else False,
              parameters=first, workers=1, progress=False, out=Path(folder) / "learn.nc")  # the writer too
    return family


def _cmd_warmup(args) -> int:
    from .engine.warmup import warm_up

    seconds = warm_up(sys.stdout)
    print(f"kernels compiled and cached in {seconds:.1f} s; sweeps and their workers now start warm")
    return 0


def _cmd_info(args) -> int:
    import numba
    import numpy as np
    import pyfftw
    import pyfftw.config

    from .results import package_versions

    print("periodyn environment")
    for name, version in package_versions().items():
        print(f"  {name:12s} {version}")
    print(f"  platform     {platform.platform()}")
    print(f"cores: {os.cpu_count()} logical, {available_cores()} usable by this process")
    print(f"numba: {numba.config.NUMBA_NUM_THREADS} threads, threading layer '{numba.config.THREADING_LAYER}'")
    blas = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
    print(f"BLAS: {blas.get('name')} {blas.get('version')}")
    for var in WORKER_THREAD_ENV:
        print(f"  {var}={os.environ.get(var, '(unset)')}")
    print(f"sweep workers run with: {', '.join(f'{k}={v}' for k, v in WORKER_THREAD_ENV.items())}")
    wisdom = pyfftw.export_wisdom()
    print(f"FFTW (pyfftw {pyfftw.__version__}): SIMD alignment {pyfftw.simd_alignment} bytes, "
          f"default threads {pyfftw.config.NUM_THREADS}, planner {pyfftw.config.PLANNER_EFFORT}, "
          f"wisdom {len(wisdom[0])}/{len(wisdom[1])}/{len(wisdom[2])} bytes (double/single/long double)")
    return 0


_COMMANDS = {"sweep": _cmd_sweep, "serve": _cmd_serve, "figures": _cmd_figures, "bench": _cmd_bench, "warmup": _cmd_warmup,
             "info": _cmd_info}


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``periodyn`` console script; returns the exit code."""
    args = build_parser().parse_args(argv)
    try:
        return _COMMANDS[args.command](args)
    except InputError as exc:
        print(f"periodyn {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except ConvergenceError as exc:
        print(f"periodyn {args.command}: failed: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:
        where = f" {exc.filename}" if exc.filename else ""
        print(f"periodyn {args.command}: error: cannot use{where} ({exc.strerror or exc}); check that the path "
              "exists, is writable and its disk has space, or give another path", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return _interrupted(args.command)
    except SystemError as exc:  # Ctrl-C that landed inside a C call
        if not caused_by_interrupt(exc):
            raise
        return _interrupted(args.command)


def _interrupted(command: str) -> int:
    hint = "; finished chunks are kept, continue with --resume" if command == "sweep" else ""
    print(f"periodyn {command}: interrupted{hint}", file=sys.stderr)
    return 130


def run() -> None:
    """The console script: a ``sweep`` in the warm server where one runs
    (:func:`periodyn.engine.server.delegate`), else :func:`main`; then exit. After an
    interrupt (chunks saved, lock released) at once: a pool abandoned mid-chunk can hold the
    exit on its result pipe."""
    if sys.argv[1:2] == ["sweep"]:
        from .engine.server import delegate

        code = delegate(sys.argv[1:])
        if code is not None:
            sys.exit(code)
    code = main()
    if code == 130:
        sys.stdout.flush(), sys.stderr.flush()
        os._exit(130)
    sys.exit(code)


if __name__ == "__main__":
    run()
