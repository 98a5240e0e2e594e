"""Fig. 4 of Schwab & Meijaard (2001): dimensionless midpoint deflection of the
slider-crank's connecting rod at omega = 150 rad/s, 2 % damping: periodic solution, and
periodic + transient from rest (averaging, eq. 24, and direct integration) over the
first period.

Everything is read from results (computed when missing through ``periodyn.plotting.figure_result``):
the periodic solution from ``sweeps/slider_crank.toml`` (the point omega = 150 rad/s, 2 %
damping), the transients from ``sweeps/slider_crank_transient.toml`` (whose periodic part
must equal the sweep's). Dashed: the full non-linear equations (4), the periodic solution
from the first point (150 rad/s) of ``sweeps/slider_crank_nonlinear.toml`` (the midpoint deflection
along its orbit, stored by the study: ``output_samples``) and the motion
from the undeformed state at rest from ``sweeps/slider_crank_nonlinear_transient.toml``."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from periodyn.plotting import figure_group, figure_result, save_figure  # noqa: E402

OMEGA = 150.0  # rad/s
DAMPING = 0.02


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = figure_result("slider_crank").sel(damping=DAMPING, omega=OMEGA, output="midpoint_deflection")
    stored = ds["harmonics"].values  # (2m+1,), l = -m..m
    tr = figure_result("slider_crank_transient").sel(output="midpoint_deflection")
    t = tr["time"].values
    theta = OMEGA * t
    periodic_output = (stored @ np.exp(1j * np.outer(ds["harmonic"].values, theta))).real
    if abs(tr.attrs["omega"] - OMEGA) > 1e-9 or not np.allclose(tr["periodic"].values, periodic_output, rtol=0,
                                                                 atol=1e-9):
        raise RuntimeError("results/slider_crank_transient.nc does not match results/slider_crank.nc at 150 rad/s; "
                           "check that sweeps/slider_crank_transient.toml and sweeps/slider_crank.toml describe the "
                           "same model, harmonics and samples")
    averaged = tr["outputs"].sel({"method": "averaging"}).values
    direct = tr["outputs"].sel({"method": "integrate"}).values
    branch = figure_group("slider_crank_nonlinear", "frequency")
    if abs(float(branch["omega"][0]) - OMEGA) > 1e-9:
        raise RuntimeError("results/slider_crank_nonlinear.nc does not start at 150 rad/s; rerun its study")
    stored_nl = branch["outputs"].isel(point=0).sel(output="midpoint_deflection").values  # (samples,)
    theta_nl = 2 * np.pi * np.arange(stored_nl.size + 1) / stored_nl.size             # one period, closed
    periodic_nl = np.append(stored_nl, stored_nl[0])
    tr_nl = figure_result("slider_crank_nonlinear_transient").sel(output="midpoint_deflection")
    if abs(tr_nl.attrs["omega"] - OMEGA) > 1e-9 or not np.allclose(tr_nl["time"].values, t, rtol=1e-12, atol=0):
        raise RuntimeError("results/slider_crank_nonlinear_transient.nc is not at 150 rad/s over the same times")
    transient_nl = tr_nl["outputs"].sel({"method": "integrate"}).values
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(theta, periodic_output, "k-", lw=1.5, label="periodic (HB, sweep results)")
    ax.plot(theta, averaged, "C0-", lw=1, label="periodic + transient (averaging)")
    ax.plot(theta, direct, "C1--", lw=1, label="periodic + transient (integration)")
    ax.plot(theta_nl, periodic_nl, "k:", lw=1.5, label="periodic, full non-linear (IHB)")
    ax.plot(theta, transient_nl, "C3:", lw=1.2, label="from rest, full non-linear (integration)")
    ax.set_xlabel(r"crank angle $\omega t$ [rad]")
    ax.set_ylabel("midpoint deflection / rod length [-]")
    ax.set_title(r"slider-crank, $\omega$ = 150 rad/s, 2 % damping")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return [save_figure(fig, pathlib.Path(out_dir) / "fig04_slider_crank_transient.png")]

if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
