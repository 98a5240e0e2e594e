"""Linearized sweep against full non-linear shooting, side by side in one run, on the same
omega grid per example (Schwab & Meijaard 2001: the linearized method is much cheaper,
especially for stiff systems):

- pendulum: eq. (29) (``periodyn.examples.pendulum``) against eq. (28)
  (``pendulum_nonlinear``), amplitude of phi;
- elliptic pendulum from elements: its linearization against ``element_dae`` of the same
  element model, amplitude of the pendulum angle;
- slider-crank (2 % damping, flexible rod): linearized sweep against shooting of the
  element model's non-linear equations (4), amplitude (half peak-to-peak) of the rod's
  midpoint deflection over its length;
- Cardan shaft (alpha = pi/6, 1 % damping, two spatial beams): linearized sweep
  (``cardan_shaft``) against shooting of the same element model's equations (4)
  (``cardan_shaft_nonlinear``), amplitude of the midpoint deflection over the length in
  the frame turning with the rigid shaft.

For each: the time of the linearized sweep (m = 12 harmonics, p = 64 samples, with the
sweep's default stability, as shooting delivers multipliers too; its time without
stability is printed as well), the time of the best
shooting periodyn offers for that example at every speed, their ratio (target >= 100), the
non-linear time per speed (target for the slider-crank <= 1 s), and the largest relative
amplitude difference over the grid (speeds chosen away from resonance). Shooting arms:

- "DOP853 from IHB": adaptive explicit shooting (rtol 1e-9, Newton tol 1e-8) started from
  the EGA-IHB orbit (12 harmonics), both timed: the only shooting of a hand-written DAE;
- "implicit from HB": ``method="implicit"`` (element models: trapezoidal one-period map in
  Numba, Richardson-extrapolated harmonics, default steps) started from the linearized
  harmonic-balance orbit at that speed (timed), no IHB; for the element pendulum both arms
  run and the faster is the one compared. ``--adaptive`` adds the DOP853 arm for the
  slider-crank too (about a minute per speed).

The last lines repeat one summary per example: the ratio of its best shooting arm.

Run: python benchmarks/bench_shooting.py [--quick]   (or: periodyn bench shooting)

Measured 2026-11-25 (OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1, 2 cores at load 12-15,
both arms equally loaded; the pendulum rows of 2026-11-24 at load 12.7 for comparison):
linearized sweep with stability / shooting seconds, ratio, non-linear s/speed, max |dA|/A
  pendulum eq. (29) vs (28)  DOP853 from IHB   57 speeds  0.220 /   9.94 s    45x  0.174  0.71 %
  pendulum from elements     DOP853 from IHB   57 speeds  0.118 /  74.74 s   636x  1.311  0.71 %
  pendulum from elements     implicit from HB  57 speeds  0.118 /  39.08 s   332x  0.686  0.71 %
  slider-crank, 2 % damping  implicit from HB  28 speeds  0.237 /  41.51 s   175x  1.482  5.87 %
  Cardan shaft, 1 % damping  implicit from HB  19 speeds  1.163 / 732.70 s   630x 38.56   0.51 %
  (2026-11-24, load 12.7: pendulum eq. (29) vs (28) 0.060 / 5.36 s, 89x)
The pendulum eq. (29) vs (28) ratio swings with the load (45-89x): its linearized sweep is
mostly fixed cost at 57 speeds.
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import periodyn  # noqa: E402
from periodyn.examples.cardan import cardan_shaft, cardan_shaft_nonlinear  # noqa: E402
from periodyn.examples.elliptic_pendulum import elliptic_pendulum_model, pendulum_from_elements  # noqa: E402
from periodyn.examples.slider_crank_rod import slider_crank, slider_crank_nonlinear  # noqa: E402
from periodyn.periodic import half_range_and_mean  # noqa: E402
from periodyn.numerics.spectra import fourier_coefficients  # noqa: E402

W0 = np.sqrt(9.81)  # rad/s, the pendulums' omega0
#: omega / omega0 away from the resonances (omega0/3, omega0/2, omega0) and instability (0.92-1.02),
#: 0.005 apart as on a response curve (57 speeds; --quick: 12 of them)
PENDULUM_GRID = np.concatenate([np.arange(0.2, 0.2801, 0.005), np.arange(0.4, 0.4401, 0.005),
                                np.arange(0.6, 0.7501, 0.005)])
#: rad/s, 2.5 apart, away from the linearized resonances near 166, 206 and 267 rad/s (28 speeds)
SLIDER_CRANK_GRID = np.concatenate([np.arange(150.0, 160.1, 2.5), np.arange(175.0, 190.1, 2.5),
                                    np.arange(230.0, 250.1, 2.5), np.arange(285.0, 300.1, 2.5)])

#: omega / omega_b of the Cardan shaft (omega_b = 767.87 rad/s), 0.01 apart, away from the resonances near
#: 1/4, 1/3, 1/2 of omega_b, the unstable zones and the deflection's deep minimum near 0.745 (19 speeds)
CARDAN_GRID = np.concatenate([np.arange(0.38, 0.4601, 0.01), np.arange(0.56, 0.6001, 0.01),
                              np.arange(0.94, 0.9801, 0.01)])


def _midpoint_amplitude(system, solution, samples=64):
    """Half peak-to-peak of an element model's first output (the slider-crank's and the
    Cardan shaft's midpoint deflection) along a non-linear orbit."""
    t = np.arange(samples) * solution.period / samples
    y = periodyn.element_outputs(system.equations.model, solution.omega, t, solution(t))
    return half_range_and_mean(fourier_coefficients(y, (samples - 1) // 2))[0][0]


def _adaptive(system, lin_model, w):
    guess = periodyn.ihb(system, w, 12, stability=None)
    return periodyn.shooting(system, w, initial=guess, tol=1e-8, rtol=1e-9)


def _implicit(system, lin_model, w):
    guess = periodyn.periodic_solution(lin_model.at(w), 12)
    return periodyn.shooting(system, w, initial=guess, integrator="implicit")


ARMS = {"DOP853 from IHB": _adaptive, "implicit from HB": _implicit}


def _nonlinear(arm, system, lin_model, omega, amplitude):
    """Shooting at every speed: (seconds, amplitudes, Newton iterations)."""
    start = time.perf_counter()
    amps, its = [], []
    for w in omega:
        sol = ARMS[arm](system, lin_model, float(w))
        amps.append(amplitude(system, sol))
        its.append(sol.iterations)
    return time.perf_counter() - start, np.array(amps), its


def _linear(model, omega, output, stability=True):
    start = time.perf_counter()
    ds = periodyn.sweep(model, omega, 12, 64, stability=stability, progress=False)
    seconds = time.perf_counter() - start
    return seconds, ds["amplitude"].sel(output=output).values


def main(quick: bool, adaptive: bool) -> None:
    both = tuple(ARMS)
    cardan = cardan_shaft(samples=64)
    cases = [
        ("pendulum eq. (29) vs (28)", periodyn.examples.pendulum(samples=64), "phi", periodyn.examples.pendulum_nonlinear(),
         lambda s, sol: sol.amplitude()[0], W0 * PENDULUM_GRID, both[:1]),
        ("pendulum from elements", pendulum_from_elements(samples=64), "pendulum",
         periodyn.element_dae(elliptic_pendulum_model()), lambda s, sol: sol.amplitude()[0], W0 * PENDULUM_GRID, both),
        ("slider-crank, 2 % damping", slider_crank(0.02, 64), "midpoint_deflection", slider_crank_nonlinear(0.02),
         _midpoint_amplitude, SLIDER_CRANK_GRID, both if adaptive else both[1:]),
        ("Cardan shaft, 1 % damping", cardan, "midpoint_deflection", cardan_shaft_nonlinear(),
         _midpoint_amplitude, cardan.metadata["omega_b"] * CARDAN_GRID, both[1:]),
    ]
    print(f"load average at start: {os.getloadavg()[0]:.2f} (2 idle cores needed for clean timings)")
    print(f"{'example':28s} {'shooting':17s} {'speeds':>6s} {'linear s':>9s} {'shooting s':>10s} {'ratio':>8s} "
          f"{'s/speed':>8s} {'max |dA|/A':>10s}  Newton iterations")
    summary = []
    for name, lin_model, output, system, amplitude, omega, arms in cases:
        if quick:
            omega = omega[::max(1, len(omega) // 12)][:12]
        _linear(lin_model, omega[:1], output)  # compile and warm up every arm
        for arm in arms:
            ARMS[arm](system, lin_model, float(omega[0]))
        t_bare = _linear(lin_model, omega, output, stability=False)[0]
        t_lin, a_lin = _linear(lin_model, omega, output)
        print(f"{name:28s} linearized sweep without stability: {t_bare:.3f} s", flush=True)
        best = None
        for arm in arms:
            t_nl, a_nl, its = _nonlinear(arm, system, lin_model, omega, amplitude)
            diff = np.max(np.abs(a_nl - a_lin) / np.abs(a_lin))
            print(f"{name:28s} {arm:17s} {len(omega):6d} {t_lin:9.3f} {t_nl:10.2f} {t_nl / t_lin:8.0f} "
                  f"{t_nl / len(omega):8.3f} {diff:10.3%}  {its}", flush=True)
            if best is None or t_nl < best[1]:
                best = (arm, t_nl, diff, a_nl)
        for w, a, b in list(zip(omega, a_lin, best[3]))[::max(1, len(omega) // 12)]:
            print(f"    omega = {w:8.3f} rad/s   amplitude linearized {a:.6g}   non-linear ({best[0]}) {b:.6g}")
        summary.append(f"{name:28s} {len(omega):3d} speeds: linearized {t_lin:.3f} s, {best[0]} {best[1]:.2f} s, "
                       f"ratio {best[1] / t_lin:.0f}x, max |dA|/A {best[2]:.2%}")
    print(f"load average at end: {os.getloadavg()[0]:.2f}")
    print("summary (best shooting arm per example; target ratio >= 100):")
    print(*summary, sep="\n")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="at most 12 speeds per example")
    parser.add_argument("--adaptive", action="store_true", help="also shoot the slider-crank with DOP853 from IHB")
    args = parser.parse_args()
    main(args.quick, args.adaptive)
