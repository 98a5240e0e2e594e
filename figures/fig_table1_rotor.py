"""Table I of Schwab & Meijaard (2001): the first eight eigenvalues of the rotor of
section 4.3 at 4000 rpm, periodyn (5 rotor elements as the paper, and refined meshes;
5 spatial beams spinning at the prescribed speed, as SPACAR) next to the paper's
"present" column and Sundararajan & Noah's, with relative differences.

Reads the results of sweeps/rotor_table1.toml (a grid over the mesh) and
sweeps/rotor_table1_spatial.toml through ``periodyn.plotting.figure_result``; writes the table as text beside the
figures."""

from __future__ import annotations

import pathlib
import sys

import numpy as np

from periodyn.examples.rotor_table1 import TABLE_I_PRESENT, TABLE_I_REFERENCE, TABLE_I_SPEED_RPM
from periodyn.plotting import figure_result  # noqa: E402



def table() -> str:
    meshes = figure_result("rotor_table1")
    spatial = figure_result("rotor_table1_spatial")
    if not np.allclose([*meshes["speed_rpm"].values, *spatial["speed_rpm"].values], TABLE_I_SPEED_RPM):
        raise ValueError(f"sweeps/rotor_table1*.toml must give the speed of Table I, {TABLE_I_SPEED_RPM} rpm")
    runs = {int(n): meshes.sel(elements=n) for n in meshes["elements"].values}
    fmt = lambda z: f"{z.real:8.2f} {z.imag:+9.2f}i"  # noqa: E731
    head = (f"{'whirl':9s} {'paper present':>19s} {'Sundararajan&Noah':>19s} "
            + " ".join(f"{f'periodyn {n} el':>19s}" for n in runs) + f" {'spatial beams 5 el':>19s}"
            + f" {'vs present':>10s} {'vs S&N':>8s} {'spatial vs present':>18s}")
    lines = [f"Rotor of section 4.3 at {TABLE_I_SPEED_RPM:.0f} rpm; eigenvalues in rad/s (stationary frame)", head]
    for k, ((whirl, present), ref) in enumerate(zip(TABLE_I_PRESENT, TABLE_I_REFERENCE)):
        ours = [complex(runs[n].eigenvalue.values[0, k]) for n in runs]
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
