"""Fig. 4 of Schwab & Meijaard (2001): dimensionless midpoint deflection of the
slider-crank's connecting rod at omega = 150 rad/s, 2 % damping: periodic solution, and
periodic + transient from rest (averaging, eq. 24, and direct integration) over the
first period.

The periodic solution is read from the results of ``sweeps/slider_crank.toml`` (the
point omega = 150 rad/s, 2 % damping); the transient, which a sweep does not store, is
computed here from the model at that speed (its periodic part must equal the stored one).
Dashed: the full non-linear equations (4), periodic solution from the first point (150
rad/s) of ``sweeps/slider_crank_nonlinear.toml`` and the transient from the undeformed
state at rest by direct integration (computed here, like the linearized transient)."""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import periodyn  # noqa: E402
import periodyn.config  # noqa: E402
from periodyn.examples.slider_crank import slider_crank, slider_crank_nonlinear  # noqa: E402
from periodyn.nonlinear import element_outputs, integrate  # noqa: E402
from periodyn.plotting import save_figure  # noqa: E402

OMEGA = 150.0  # rad/s
DAMPING = 0.02


def main(out_dir: pathlib.Path) -> list[pathlib.Path]:
    ds = periodyn.config.ensure("slider_crank").sel(damping=DAMPING, omega=OMEGA, output="midpoint_deflection")
    stored = ds["harmonics"].values  # (2m+1,), l = -m..m
    t = np.linspace(0.0, 2 * np.pi / OMEGA, 401)
    theta = OMEGA * t
    periodic_output = (stored @ np.exp(1j * np.outer(ds["harmonic"].values, theta))).real
    system = slider_crank(DAMPING, int(ds.attrs["samples"])).at(OMEGA)
    periodic = periodyn.periodic_solution(system, int(ds.attrs["harmonics"]))
    y0 = np.zeros(2 * system.n)
    averaged = periodyn.transient(system, periodic, y0, t, method="averaging")
    direct = periodyn.transient(system, periodic, y0, t, method="integrate")
    if not np.allclose(averaged.periodic_outputs[:, 0], periodic_output, rtol=0, atol=1e-9):
        raise RuntimeError("results/slider_crank.nc does not match the model; rerun periodyn sweep "
                           "sweeps/slider_crank.toml --out results/slider_crank.nc")
    system_nl = slider_crank_nonlinear(DAMPING)
    model = system_nl.equations.model
    branch = periodyn.config.ensure("slider_crank_nonlinear")["frequency"]
    if abs(branch.omega[0] - OMEGA) > 1e-9:
        raise RuntimeError("results/slider_crank_nonlinear.nc does not start at 150 rad/s; rerun its study")
    orbit = branch.solutions[0]
    periodic_nl = element_outputs(model, OMEGA, t, orbit(t))[:, 0]
    start = orbit(0.0)[0], orbit.velocity(0.0)[0]
    end = integrate(system_nl, OMEGA, (0.0, t[-1]), *start, t_eval=t[-1:], rtol=1e-9, atol=1e-11).q[-1]
    size = np.abs(orbit(t)).max()
    print(f"non-linear orbit at 150 rad/s: integrated over one period it returns to {np.abs(end - start[0]).max():.2e} "
          f"rad (orbit size {size:.3g} rad, IHB spectral tail {orbit.tail:.1e})")
    if np.abs(end - start[0]).max() > 10 * orbit.tail * size:
        raise RuntimeError("the stored non-linear orbit is not periodic under direct integration; rerun its study")
    history = integrate(system_nl, OMEGA, (0.0, t[-1]), np.zeros(system_nl.n), np.zeros(system_nl.n), t_eval=t,
                        rtol=1e-9, atol=1e-11)
    transient_nl = element_outputs(model, OMEGA, t, history.q)[:, 0]
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(theta, periodic_output, "k-", lw=1.5, label="periodic (HB, sweep results)")
    ax.plot(theta, averaged.outputs[:, 0], "C0-", lw=1, label="periodic + transient (averaging)")
    ax.plot(theta, direct.outputs[:, 0], "C1--", lw=1, label="periodic + transient (integration)")
    ax.plot(theta, periodic_nl, "k:", lw=1.5, label="periodic, full non-linear (IHB)")
    ax.plot(theta, transient_nl, "C3:", lw=1.2, label="from rest, full non-linear (integration)")
    ax.set_xlabel(r"crank angle $\omega t$ [rad]")
    ax.set_ylabel("midpoint deflection / rod length [-]")
    ax.set_title(r"slider-crank, $\omega$ = 150 rad/s, 2 % damping")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return [save_figure(fig, pathlib.Path(out_dir) / "fig04_slider_crank_transient.png")]

if __name__ == "__main__":
    print(*main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "png"), sep="\n")
