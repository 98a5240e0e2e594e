"""Fig. 12 of Schwab & Meijaard (2001): amplitudes (log scale) of harmonics 0-6 of the
Cardan drive shaft's twist angle over 0 < omega/omega_b < 1; the odd harmonics vanish by
the symmetry of the system (drawn at round-off level), harmonic 0 is the mean twist.

Reads the results of ``sweeps/cardan_shaft.toml`` (computed and stored on first use)."""

from __future__ import annotations

import pathlib
import sys


sys.path.insert(0, str(pathlib.Path(__file__).parent))
from fig09_cardan_max_deflection import NAME  # noqa: E402
from fig11_cardan_deflection_harmonics import harmonic_panels  # noqa: E402
from periodyn.plotting import figure_result  # noqa: E402


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = figure_result(NAME)
    return [harmonic_panels(ds, "twist", r"the twist $\varphi$ [rad]",
                            pathlib.Path(out_dir) / "fig12_cardan_twist_harmonics.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
