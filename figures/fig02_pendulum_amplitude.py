"""Schwab & Meijaard (2001) Fig. 2: amplitude of the periodic solution of the elliptic
pendulum, zeta = 0.01, 0 < omega/omega0 < 0.9: linearized eq. (29) from
sweeps/pendulum.toml (solid) and the full non-linear eq. (28) by shooting with arc-length
continuation from sweeps/pendulum_nonlinear.toml (dashed; the resonance peak bends backwards
through two folds)."""

from __future__ import annotations

import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import periodyn.studies.spec  # noqa: E402
from periodyn.plotting import save_figure  # noqa: E402


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = periodyn.studies.spec.ensure("pendulum")
    r = ds["omega_over_omega0"].values
    amp = ds["amplitude"].sel(output="phi").values
    keep = r <= 0.9
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(r[keep], amp[keep], "k-", lw=1.2, label="linearized, eq. (29)")
    w0 = float(ds["omega_over_omega0"].attrs["reference_frequency"])
    branch = periodyn.studies.spec.ensure("pendulum_nonlinear")["frequency"]
    ax.plot(np.asarray(branch.omega) / w0, np.asarray(branch.amplitude)[:, 0], "k--", lw=1.0,
            label="full non-linear, eq. (28), shooting")
    ax.set_xlabel(r"$\omega/\omega_0$")
    ax.set_ylabel(r"$\Delta\hat\varphi$ [rad]")
    ax.set_xlim(0, 0.9)
    ax.set_ylim(0, None)
    ax.set_title(r"Elliptic pendulum, $\zeta = 0.01$ (Fig. 2)")
    ax.legend(loc="upper left")
    fig.tight_layout()
    return [save_figure(fig, out_dir / "fig02_pendulum_amplitude.png")]


if __name__ == "__main__":
    print(*main(pathlib.Path(__file__).parent / "png"), sep="\n")
