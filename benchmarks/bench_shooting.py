"""Linearized sweep against full non-linear shooting, side by side in one run, on the same
omega grid per example (Schwab & Meijaard 2001: the linearized method is much cheaper,
especially for stiff systems):

- pendulum: eq. (29) (``periodyn.examples.pendulum``) against eq. (28)
  (``pendulum_nonlinear``), amplitude of phi;
- elliptic pendulum from elements: its linearization against ``element_dae`` of the same
  element model, amplitude of the pendulum angle;
- slider-crank (2 % damping, flexible rod): linearized sweep against shooting of the
  element model's non-linear equations (4), amplitude (half peak-to-peak) of the rod's
  midpoint deflection over its length.

For each: the time of the linearized sweep (m = 12 harmonics, p = 64 samples, no
stability), the time of shooting at every speed (started from the EGA-IHB orbit, which is
timed with it; multipliers from the monodromy matrix come with it), their ratio (target
>= 100), the non-linear time per speed (target for the slider-crank <= 1 s), and the
largest relative amplitude difference over the grid (speeds chosen away from resonance).

Run: python benchmarks/bench_shooting.py [--quick]   (or: periodyn bench shooting)
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import periodyn  # noqa: E402
from periodyn.examples.elliptic_pendulum import elliptic_pendulum_model, pendulum_from_elements  # noqa: E402
from periodyn.examples.slider_crank import slider_crank, slider_crank_nonlinear  # noqa: E402
from periodyn.periodic import half_range_and_mean  # noqa: E402
from periodyn.spectra import fourier_coefficients  # noqa: E402

W0 = np.sqrt(9.81)  # rad/s, the pendulums' omega0
#: omega / omega0 away from the resonances (omega0/3, omega0/2, omega0) and instability (0.92-1.02)
PENDULUM_GRID = np.array([0.2, 0.22, 0.24, 0.26, 0.28, 0.4, 0.42, 0.44, 0.6, 0.65, 0.7, 0.75])


def _midpoint_amplitude(system, solution, samples=64):
    """Half peak-to-peak of the slider-crank's non-linear midpoint deflection on an orbit."""
    t = np.arange(samples) * solution.period / samples
    y = periodyn.element_outputs(system.equations.model, solution.omega, t, solution(t))
    return half_range_and_mean(fourier_coefficients(y, (samples - 1) // 2))[0][0]


def _nonlinear(system, omega, amplitude):
    """Shooting at every speed from the IHB orbit: (seconds, amplitudes, Newton iterations)."""
    start = time.perf_counter()
    amps, its = [], []
    for w in omega:
        guess = periodyn.ihb(system, float(w), 12, stability=None)
        sol = periodyn.shooting(system, float(w), initial=guess, tol=1e-8, rtol=1e-9)
        amps.append(amplitude(system, sol))
        its.append(sol.iterations)
    return time.perf_counter() - start, np.array(amps), its


def _linear(model, omega, output):
    start = time.perf_counter()
    ds = periodyn.sweep(model, omega, 12, 64, stability=False, progress=False)
    seconds = time.perf_counter() - start
    return seconds, ds["amplitude"].sel(output=output).values


def main(quick: bool) -> None:
    cases = [
        ("pendulum eq. (29) vs (28)", periodyn.examples.pendulum(samples=64), "phi", periodyn.examples.pendulum_nonlinear(),
         lambda s, sol: sol.amplitude()[0], W0 * PENDULUM_GRID),
        ("pendulum from elements", pendulum_from_elements(samples=64), "pendulum",
         periodyn.element_dae(elliptic_pendulum_model()), lambda s, sol: sol.amplitude()[0], W0 * PENDULUM_GRID),
        ("slider-crank, 2 % damping", slider_crank(0.02, 64), "midpoint_deflection", slider_crank_nonlinear(0.02),
         _midpoint_amplitude, np.array([160.0, 180.0, 240.0, 290.0])),
    ]
    print(f"load average at start: {os.getloadavg()[0]:.2f} (2 idle cores needed for clean timings)")
    print(f"{'example':28s} {'speeds':>6s} {'linear s':>9s} {'shooting s':>10s} {'ratio':>8s} {'s/speed':>8s} "
          f"{'max |dA|/A':>10s}  Newton iterations")
    for name, lin_model, output, system, amplitude, omega in cases:
        if quick:
            omega = omega[:2]
        _linear(lin_model, omega[:1], output)  # compile and warm up both arms
        periodyn.ihb(system, float(omega[0]), 12, stability=None)
        t_lin, a_lin = _linear(lin_model, omega, output)
        t_nl, a_nl, its = _nonlinear(system, omega, amplitude)
        diff = np.max(np.abs(a_nl - a_lin) / np.abs(a_lin))
        print(f"{name:28s} {len(omega):6d} {t_lin:9.3f} {t_nl:10.2f} {t_nl / t_lin:8.0f} {t_nl / len(omega):8.2f} "
              f"{diff:10.3%}  {its}", flush=True)
        for w, a, b in zip(omega, a_lin, a_nl):
            print(f"    omega = {w:8.3f} rad/s   amplitude linearized {a:.6g}   non-linear {b:.6g}")
    print(f"load average at end: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="two speeds per example")
    main(parser.parse_args().quick)
