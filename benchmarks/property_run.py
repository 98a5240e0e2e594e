"""Property-based run over the inputs a user gives periodyn, with physics as the oracle.

Seeded random inputs of five kinds, valid ones and ones with a single broken field:
sweep files (the elliptic pendulum, through the ``periodyn sweep`` command), element
files (sweeps/elliptic_pendulum_elements.toml with its geometry, mass and damper
changed), rotor files (shafts, bearings, disks), DAE builders (the seed-2 examples,
Duffing, the non-linear pendulum) and API arguments (``RheoLinear.from_samples`` +
``characteristic_exponents`` / ``periodic_solution``, ``sweep``, ``campbell``,
``continuation`` ranges). Each input ends in one of:

- ran correctly: every solved point agrees with an independent oracle
  (benchmarks/property_oracles.py: DOP853 on the equations written out there): the
  stability verdict against the monodromy where log max|mu| is at least 0.02 from 0,
  amplitudes within 5 % of the periodic orbit from integration (where no multiplier is
  within 0.05 of 1), Liouville's sum of the exponents' real parts (and the multipliers'
  product of shooting orbits); rotor files: the same eigenvalues as the rotor built in
  Python, no growing mode with bearing damping, none damped without; points flagged as
  failed (with their reason) count as answered;
- refused cleanly: InputError / exit code 2 with a message, or ConvergenceError naming why;
- silent wrong: a result that disagrees with the oracle, or a broken input accepted;
- traceback: any other exception (or a command that prints one).

Run: PYTHONPATH=src python benchmarks/property_run.py [--examples 2000] [--seed 0]
(338-969 s in one process on 2 shared cores). Prints the summary table and the first few
failures of each kind with the input that caused them.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import sys
import tempfile
import time
import traceback
import warnings
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import property_api  # noqa: E402
import property_inputs  # noqa: E402
from property_oracles import Wrong  # noqa: E402

KINDS = {**property_inputs.KINDS, **property_api.KINDS}

OUTCOMES = ("ran correctly", "refused cleanly", "silent wrong", "traceback")
#: share of the examples per kind
SHARES = {"rotor files": 0.2, "API arguments": 0.2, "DAE builders": 0.2, "element files": 0.15, "sweep files": 0.25}


def classify(check, case, workdir: Path) -> tuple[str, str, int]:
    """Run one case through its check -> (outcome, detail, flagged points)."""
    from periodyn.errors import ConvergenceError, InputError

    err = io.StringIO()
    try:
        with warnings.catch_warnings(), contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            warnings.simplefilter("ignore")
            flagged = check(case, workdir)
    except Wrong as exc:
        return "silent wrong", str(exc), 0
    except (InputError, ConvergenceError) as exc:
        if not str(exc):
            return "traceback", f"{type(exc).__name__} without a message", 0
        return "refused cleanly", str(exc)[:160], 0
    except Exception:  # noqa: BLE001 - what the run is looking for
        return "traceback", traceback.format_exc(limit=-3), 0
    if "Traceback" in err.getvalue():
        return "traceback", err.getvalue()[-600:], 0
    if flagged is None:
        return "refused cleanly", err.getvalue().strip()[-160:], 0
    return "ran correctly", "", flagged


def print_table(kinds, table, flagged, file=None) -> Counter:
    """The summary table (inputs by kind and outcome); returns the totals."""
    file = file or sys.stdout
    total = Counter()
    width = max(map(len, kinds)) + 2
    print(f"\n{'inputs':<{width}}{'total':>7}" + "".join(f"{o:>17}" for o in OUTCOMES) + f"{'flagged points':>16}",
          file=file)
    for kind in kinds:
        total.update(table[kind])
        print(f"{kind:<{width}}{sum(table[kind].values()):>7}" + "".join(f"{table[kind][o]:>17}" for o in OUTCOMES)
              + f"{flagged[kind]:>16}", file=file)
    print(f"{'all':<{width}}{sum(total.values()):>7}" + "".join(f"{total[o]:>17}" for o in OUTCOMES)
          + f"{sum(flagged.values()):>16}", file=file, flush=True)
    return total


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--examples", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--only", choices=list(SHARES), help="run one kind only")
    parser.add_argument("--show-refused", action="store_true", help="print each refusal with its input")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    kinds = [args.only] if args.only else list(SHARES)
    shares = np.array([SHARES[k] for k in kinds])
    counts = np.floor(shares / shares.sum() * args.examples).astype(int)
    counts[0] += args.examples - counts.sum()
    table = defaultdict(Counter)
    flagged = Counter()
    failures = defaultdict(list)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        for kind, count in zip(kinds, counts):
            generate, check = KINDS[kind]
            t0 = time.perf_counter()
            for i in range(count):
                case = generate(rng)
                workdir = Path(tmp) / f"{kind.split()[0]}{i}"
                workdir.mkdir()
                outcome, detail, points = classify(check, case, workdir)
                table[kind][outcome] += 1
                flagged[kind] += points
                if args.show_refused and outcome == "refused cleanly":
                    print(f"refused {case!r}\n  {detail}", file=sys.stderr)
                if outcome in ("silent wrong", "traceback"):
                    print(f"{outcome}: {case!r}\n  {detail}", file=sys.stderr, flush=True)
                if outcome in ("silent wrong", "traceback") and len(failures[kind]) < 5:
                    failures[kind].append((case, detail))
            print(f"{kind}: {count} inputs in {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
            print_table([k for k in kinds if k in table], table, flagged, sys.stderr)
    total = print_table(kinds, table, flagged)
    print(f"\n{sum(total.values())} inputs in {time.perf_counter() - start:.0f} s (seed {args.seed})")
    for kind, items in failures.items():
        for case, detail in items:
            print(f"\n[{kind}] {case!r}\n  {detail}")
    return 1 if total["silent wrong"] or total["traceback"] else 0


if __name__ == "__main__":
    sys.exit(main())
