"""Table I of Schwab & Meijaard (2001): the first eight eigenvalues of the rotor of
section 4.3 at 4000 rpm, periodyn (5 rotor elements as the paper, and refined meshes;
5 spatial beams spinning at the prescribed speed, as SPACAR) next to the paper's
"present" column and Sundararajan & Noah's, with relative differences.

Reads (or computes once and stores) results/table1_rotor_<n>el.nc and
results/table1_rotor_spatial_5el.nc made by periodyn.rotor.diagram; writes the table as
text beside the figures."""

from __future__ import annotations

import pathlib
import sys

import numpy as np

from periodyn.studies.spec import project_root
from periodyn.examples import rotor
from periodyn.examples.rotor_table1 import TABLE_I_PRESENT, TABLE_I_REFERENCE, TABLE_I_SPEED_RPM
from periodyn.rotor import stored_campbell

MESHES = (5, 20, 80)


def table() -> str:
    speed = TABLE_I_SPEED_RPM * np.pi / 30.0
    results = project_root() / "results"
    runs = {n: stored_campbell(results / f"table1_rotor_{n}el.nc", rotor(n), [speed], modes=8) for n in MESHES}
    spatial = stored_campbell(results / "table1_rotor_spatial_5el.nc", rotor(5, shaft="spatial"), [speed], modes=8)
    fmt = lambda z: f"{z.real:8.2f} {z.imag:+9.2f}i"  # noqa: E731
    head = (f"{'whirl':9s} {'paper present':>19s} {'Sundararajan&Noah':>19s} "
            + " ".join(f"{f'periodyn {n} el':>19s}" for n in MESHES) + f" {'spatial beams 5 el':>19s}"
            + f" {'vs present':>10s} {'vs S&N':>8s} {'spatial vs present':>18s}")
    lines = [f"Rotor of section 4.3 at {TABLE_I_SPEED_RPM:.0f} rpm; eigenvalues in rad/s (stationary frame)", head]
    for k, ((whirl, present), ref) in enumerate(zip(TABLE_I_PRESENT, TABLE_I_REFERENCE)):
        ours = [complex(runs[n].eigenvalue.values[0, k]) for n in MESHES]
        beams = complex(spatial.eigenvalue.values[0, k])
        ok = "" if runs[5].whirl.values[0, k] == spatial.whirl.values[0, k] == whirl else " (whirl differs)"
        lines.append(f"{whirl:9s} {fmt(present)} {fmt(ref)} " + " ".join(fmt(z) for z in ours) + f" {fmt(beams)}"
                     + f" {abs(ours[0] - present) / abs(present):10.3%} {abs(ours[0] - ref) / abs(ref):8.3%}"
                     + f" {abs(beams - present) / abs(present):18.3%}{ok}")
    return "\n".join(lines)


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    text = table()
    print(text)
    path = pathlib.Path(out_dir) / "table1_rotor.txt"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text + "\n")
    return [path]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
