"""Sweep engine benchmark, measured in one run on the shipped sweeps/pendulum.toml
(m = 12 harmonics, p = 64 samples, with stability):

1. throughput (speeds/s) for 100, 1000 and 10000 speeds on 1 and 2 worker processes and
   the parallel efficiency t1 / (2 t2) (target >= 80 % at 10000 speeds) within one Python
   process (the fork server that starts workers is then running), the pool start-up time
   (first pool of a process, later pools), and the same 10000-speed sweep as two cold
   ``periodyn sweep`` commands (interpreter and fork server start included). Wall-clock
   efficiency needs two idle cores: the load average is printed at start and end;
2. checkpointing: the same 10000-speed 2-worker sweep writing <out>.parts/ chunks and the
   merged netCDF file, against the sweep without checkpoints whose dataset is then saved
   to the same kind of file (the result file is written either way), as wall-time
   difference and as the time spent in the writes;
3. resume: that sweep interrupted at half (as Ctrl-C would) and resumed; overhead =
   (first half + resume - uninterrupted) / uninterrupted. Targets for 2 and 3: < 5 %.

Run: python benchmarks/bench_sweep.py [--quick]   (or: periodyn bench sweep)
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import importlib  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from periodyn.studies.spec import load_sweep_file  # noqa: E402
from periodyn.results import load, save  # noqa: E402

engine = importlib.import_module("periodyn.engine.front")
from periodyn.engine.checkpoint import Checkpoint  # noqa: E402

SWEEP_FILE = Path(__file__).resolve().parents[1] / "sweeps" / "pendulum.toml"


class Interrupt(Exception):
    """Stops a sweep part-way, like Ctrl-C."""


def run(spec, n: int, workers: int, out=None, resume=False, progress=False, save_to=None) -> float:
    """Wall time of one sweep, s; save_to: also write its dataset there (no checkpoints)."""
    t0 = time.perf_counter()
    ds = engine.sweep_file(spec, omega=(0.01, 1.4, n), out=out, workers=workers, resume=resume, progress=progress)
    if save_to is not None:
        save(ds, save_to)
    return time.perf_counter() - t0


def run_command(n: int, workers: int, out: Path) -> float:
    """Wall time of a cold ``periodyn sweep`` process, s."""
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "periodyn.cli", "sweep", str(SWEEP_FILE), "--omega", f"0.01:1.4:{n}",
                    "--workers", str(workers), "--out", str(out), "--quiet"], check=True)
    return time.perf_counter() - t0


def timed_writes():
    """Wrap checkpoint and result-file writes to add up the time spent in them."""
    spent = {"chunks": 0.0, "merge": 0.0}
    write, finish = Checkpoint.write, Checkpoint.finish

    def timed_write(self, chunk):
        t0 = time.perf_counter()
        write(self, chunk)
        spent["chunks"] += time.perf_counter() - t0

    def timed_finish(self, ds):
        t0 = time.perf_counter()
        finish(self, ds)
        spent["merge"] += time.perf_counter() - t0

    Checkpoint.write, Checkpoint.finish = timed_write, timed_finish
    return spent


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="100 and 1000 speeds only")
    args = parser.parse_args()
    spec = load_sweep_file(SWEEP_FILE)
    sizes = (100, 1000) if args.quick else (100, 1000, 10000)
    print(f"sweep file {SWEEP_FILE.name}: m = {spec.harmonics}, p = {spec.samples}, stability = {spec.stability}; "
          f"{engine.available_cores()} cores, load average {os.getloadavg()[0]:.1f} at start")
    with tempfile.TemporaryDirectory() as tmp:
        run(spec, 20, 1, out=Path(tmp) / "warm.nc")  # compile/warm caches and the netCDF stack in this process
    first, startup = run(spec, 2, 2), run(spec, 2, 2)
    print(f"2-worker sweep of 2 speeds: {first:.2f} s as the first pool of this process (starts the fork "
          f"server, which imports periodyn once), {startup:.2f} s later")

    print(f"\n{'speeds':>7} {'1 worker':>16} {'2 workers':>16} {'efficiency':>11}")
    times = {}
    for n in sizes:
        t1, t2 = run(spec, n, 1), run(spec, n, 2)
        times[n] = (t1, t2)
        print(f"{n:>7} {n / t1:>9.0f} spd/s {n / t2:>9.0f} spd/s {t1 / (2 * t2):>10.0%}")
    with tempfile.TemporaryDirectory() as tmp:
        n = sizes[-1]
        c1, c2 = run_command(n, 1, Path(tmp) / "a.nc"), run_command(n, 2, Path(tmp) / "b.nc")
        print(f"cold 'periodyn sweep' of {n} speeds (with writing the file): {c1:.2f} s on 1 worker, {c2:.2f} s "
              f"on 2 -> efficiency {c1 / (2 * c2):.0%}")

    n = sizes[-1]
    spent = timed_writes()
    with tempfile.TemporaryDirectory() as tmp:
        t_plain = run(spec, n, 2, save_to=Path(tmp) / "plain.nc")
        out = Path(tmp) / "bench.nc"
        t_ckpt = run(spec, n, 2, out=out)
        size = out.stat().st_size
        out.unlink()
        written = dict(spent)

        def stop_half(done, total):
            if done >= total // 2:
                raise Interrupt

        t0 = time.perf_counter()
        try:
            run(spec, n, 2, out=out, progress=stop_half)
        except Interrupt:
            pass
        t_first = time.perf_counter() - t0
        t_resume = run(spec, n, 2, out=out, resume=True)
        t0 = time.perf_counter()
        save(load(out), Path(tmp) / "copy.nc")
        t_save = time.perf_counter() - t0

    print(f"\ncheckpointing, {n} speeds on 2 workers, result file written either way: {t_plain:.2f} s without "
          f"checkpoints (sweep, then save), {t_ckpt:.2f} s with -> wall-time overhead {(t_ckpt - t_plain) / t_plain:+.1%}")
    print(f"  time in chunk writes {written['chunks']:.3f} s ({written['chunks'] / t_ckpt:.1%}), final merge to "
          f"netCDF {written['merge']:.3f} s ({written['merge'] / t_ckpt:.1%}); file {size / 1e6:.1f} MB "
          f"(plain save {t_save:.3f} s)")
    print(f"resume: interrupted at half after {t_first:.2f} s, resumed in {t_resume:.2f} s -> "
          f"overhead {(t_first + t_resume - t_ckpt) / t_ckpt:+.1%} of the uninterrupted {t_ckpt:.2f} s "
          f"(includes one more pool start-up, {startup:.2f} s, and the chunks in flight at the interrupt)")
    print(f"load average {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
