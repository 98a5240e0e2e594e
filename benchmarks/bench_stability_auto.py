"""Stability method "auto" against each method, one core, measured side by side.

1. Every shipped rheo-linear sweep file (pendulum, elliptic pendulum from elements,
   slider-crank, slider-crank from elements) at its harmonics, and the slider-crank
   scaled to 4-32 rod elements at m = 4-64: speeds per second of SpeedSolver.solve_many
   with stability by "dense", "sparse" and "magnus" and by "auto", and the ratio of the
   best method's rate to auto's (auto/best-Hill: the best of dense and sparse only),
   each on speeds spread evenly over the range. A method whose estimated time per speed
   is above the budget is skipped ("-").
2. With --sweep: periodyn.sweep of 1000 speeds (fewer for the large model), default
   options (stability "auto"), on --workers processes, speeds/s (a cold start included
   when run first).
3. With --errors: the ladder's certified error against the true error of log max|mu|
   (fine Magnus references) per model, and the error of the fixed 128-step method.
4. With --per-speed: stability alone, ms per speed on one core, of the certified Magnus
   ladder as "auto" uses it (both orders, chosen per speed), of order 6 alone, of order
   4 alone (the previous ladder's integrator) and of dense Hill at m = 12 (stacked),
   best of interleaved rounds on the same speeds, with the ladders' steps and whether
   all give the same verdicts (pendulum, slider-crank 2 and 8 rod elements, Cardan
   shaft).

Run: python benchmarks/bench_stability_auto.py [--budget 3] [--quick] [--sweep] [--workers 2] [--per-speed]
     [--errors [--large]]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import periodyn  # noqa: E402
from periodyn.speeds import SpeedSolver  # noqa: E402
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model  # noqa: E402
from periodyn.studies.spec import load_sweep_file, project_root  # noqa: E402
from periodyn.stability.hill import dense_exponents_batch, shift_frequencies  # noqa: E402
from periodyn.stability.methods import method_costs  # noqa: E402
from periodyn.model.linearization import omega_split  # noqa: E402
from periodyn.kernels.solvers.magnus_ladder import streamed_moduli  # noqa: E402
from periodyn.stability.magnus import MagnusLadder  # noqa: E402

METHODS = ("dense", "sparse", "magnus", "auto")


def scaled_slider_crank(elements: int, samples: int = 64):
    """The slider-crank with ``elements`` rod elements, 2 % damping in the first mode."""
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=elements))
    return omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=elements), samples)


def pilot(solver, omegas, budget):
    """How many speeds solve_many treats in about budget / 3 seconds (after a warm-up),
    timed from the low end of the range (where "auto" and Magnus cost the most)."""
    solver.solve_many(omegas[:1])  # jit, cached terms
    done, t0 = 0, time.perf_counter()
    while done < omegas.size and (done == 0 or time.perf_counter() - t0 < budget / 3):
        step = max(1, min(omegas.size - done, done or 1))
        solver.solve_many(omegas[done: done + step])
        done += step
    return done


def row(name, model, m, omegas, budget, rounds=3):
    """Best of ``rounds`` interleaved timings of each method on speeds spread evenly over
    the range (as many as the method treats in about budget / 3 s)."""
    solvers = {k: SpeedSolver(model, m, stability=k) for k in METHODS}
    if method_costs(solvers["dense"].pattern)[0] > budget:
        del solvers["dense"]
    per_shift = method_costs(solvers["sparse"].pattern)[1]
    if per_shift * shift_frequencies(solvers["sparse"].harmonic.at(omegas[0])).size > budget:
        del solvers["sparse"]
    spread = {k: omegas[np.unique(np.linspace(0, omegas.size - 1, pilot(s, omegas, budget)).round().astype(int))]
              for k, s in solvers.items()}  # evenly over the range
    times = {k: np.inf for k in solvers}
    for _ in range(rounds):
        for k, s in solvers.items():
            t0 = time.perf_counter()
            s.solve_many(spread[k])
            times[k] = min(times[k], (time.perf_counter() - t0) / spread[k].size)
    rates = {k: 1.0 / times[k] if k in times else np.nan for k in METHODS}
    choices = [c for c, _ in solvers["auto"].stability_methods(omegas)]
    auto_choice = "/".join(f"{c} {choices.count(c)}" for c in sorted(set(choices)))
    hill = np.nanmax([rates["dense"], rates["sparse"]])
    best = np.nanmax([rates[k] for k in ("dense", "sparse", "magnus")])
    cells = "".join(f"{rates[k]:10.1f}" if np.isfinite(rates[k]) else f"{'-':>10}" for k in METHODS)
    print(f"{name:<18}{model.n:4d}{m:4d}{cells}   {hill / rates['auto']:13.2f}  {best / rates['auto']:9.2f}  "
          f"{auto_choice}", flush=True)


def shipped(name: str):
    """Model (last grid point), speeds (rad/s) and harmonics of a shipped sweep file."""
    spec = load_sweep_file(project_root() / "sweeps" / f"{name}.toml")
    plan = spec.plan()
    model = plan.model(**{k: v[-1] for k, v in plan.parameters.items()}) if plan.parameters else plan.model
    return model, plan.omega, spec.harmonics


def sweep_rates(workers: int, rounds: int = 1) -> None:
    """periodyn.sweep with default options on ``workers`` processes, speeds/s."""
    w0 = periodyn.examples.pendulum().metadata["omega0"]
    cases = [("pendulum", periodyn.examples.pendulum(samples=64), np.linspace(0.002, 1.4, 1000) * w0),
             ("slider-crank", periodyn.examples.slider_crank(damping=0.02), np.linspace(150.0, 300.0, 1000)),
             ("slider-crank x32", scaled_slider_crank(32), np.linspace(150.0, 300.0, 60))]
    print(f"\nperiodyn.sweep, m = 12, default options (stability auto), {workers} workers")
    for name, model, omegas in cases:
        for _ in range(rounds):
            t0 = time.perf_counter()
            ds = periodyn.sweep(model, omegas, 12, workers=workers, progress=False)
            dt = time.perf_counter() - t0
            print(f"{name:<18} {omegas.size:5d} speeds {dt:8.2f} s {omegas.size / dt:10.1f} speeds/s   "
                  f"{ds.attrs['stability_methods'].split(';')[0]}", flush=True)


def per_speed(rounds: int = 3, m: int = 12) -> None:
    """Stability alone per speed: Magnus ladders of order 6 and 4 against stacked dense Hill."""
    w0 = periodyn.examples.pendulum().metadata["omega0"]
    cardan = periodyn.examples.cardan_shaft()
    wb = cardan.metadata["omega_b"]
    cases = [("pendulum", periodyn.examples.pendulum(samples=64), np.linspace(0.1, 1.4, 64) * w0),
             ("slider-crank", periodyn.examples.slider_crank(damping=0.02), np.linspace(150.0, 300.0, 32)),
             ("cardan", cardan, np.linspace(0.02, 0.999, 32) * wb),
             ("slider-crank x8", scaled_slider_crank(8), np.linspace(150.0, 300.0, 8))]
    print(f"\nstability alone, ms per speed, one core; dense Hill at m = {m}")
    print(f"{'model':<18}{'n':>4}{'speeds':>7}{'ladder':>9}{'magnus6':>9}{'magnus4':>9}{'dense':>10}{'lad/4':>7}"
          f"{'lad/dense':>10}   steps ladder / 6 / 4 (median/max)   orders   same verdicts")
    for name, model, w in cases:
        ladders = {k: MagnusLadder(*model._power_spectra[:3], order=k) for k in (None, 6, 4)}
        solver = SpeedSolver(model, m, stability="dense")
        arms = {"ladder": lambda: ladders[None].solve(w, np.inf), "magnus6": lambda: ladders[6].solve(w, np.inf),
                "magnus4": lambda: ladders[4].solve(w, np.inf),
                "dense": lambda: dense_exponents_batch(solver.harmonic.real_first_order_many(w), w, m, model.n)[0]}
        results = {k: f() for k, f in arms.items()}  # warm-up (jit, cached terms)
        best = {k: np.inf for k in arms}
        for _ in range(rounds):
            for k, f in arms.items():
                t0 = time.perf_counter()
                f()
                best[k] = min(best[k], (time.perf_counter() - t0) / w.size)
        period = 2 * np.pi / w
        magnus = ("ladder", "magnus6", "magnus4")
        verdicts = [results[k].exponents.real.max(axis=1) * period <= 1e-6 for k in magnus]
        dense = results["dense"].real.max(axis=1) * period <= 1e-6
        certified = np.logical_and.reduce([results[k].accepted for k in magnus])
        same = int(np.logical_and.reduce([v == dense for v in verdicts])[certified].sum())
        steps = " ".join(f"{int(np.median(results[k].steps))}/{results[k].steps.max()}" for k in magnus)
        orders = results["ladder"].order.tolist()
        used = "/".join(f"{k}:{orders.count(k)}" for k in (6, 4) if orders.count(k))
        ms = {k: 1e3 * v for k, v in best.items()}
        print(f"{name:<18}{model.n:4d}{w.size:7d}{ms['ladder']:9.3f}{ms['magnus6']:9.3f}{ms['magnus4']:9.3f}"
              f"{ms['dense']:10.3f}{ms['ladder'] / ms['magnus4']:7.2f}{ms['ladder'] / ms['dense']:10.3f}   "
              f"{steps:<33}{used:<10}{same}/{int(certified.sum())} certified", flush=True)


def certified_errors(large: bool = False) -> None:
    """The ladder's certified error against the true error of log max|mu| (a fine Magnus
    reference of the order that converges on the model), and the error of the fixed-step
    method "magnus" (order 4, 128 steps, no estimate) at the same speeds."""
    w0 = periodyn.examples.pendulum().metadata["omega0"]
    cardan = periodyn.examples.cardan_shaft()
    wb = cardan.metadata["omega_b"]
    cases = [("pendulum", periodyn.examples.pendulum(samples=64), np.linspace(0.02, 1.4, 40) * w0, 6, 2048),
             ("cardan", cardan, np.geomspace(0.003, 0.999, 40) * wb, 6, 4096)]
    # order 6 breaks down on the stiffest slider-cranks (NaN at 4096 steps with 32 rod elements)
    cases += [(f"slider-crank x{el}", scaled_slider_crank(el), np.linspace(150.0, 300.0, 12), 4 if el > 16 else 6,
               2048 if el > 16 else 4096) for el in ((2, 4, 8, 16, 32) if large else (2, 4, 8, 16))]
    def growth(ladder, w, steps, order):
        """log max|mu| (S,) with ``steps`` steps of ``order``, terms built 64 steps at a time."""
        d, out = 2 * ladder.n, np.empty(w.size)
        exps, mod, Phi = np.empty(d, complex), np.empty(d), np.empty((d, d))
        for i, omega in enumerate(w):
            streamed_moduli(ladder._rows, ladder.n, *ladder.powers, steps, order // 2, ladder.span, ladder.scale, 64,
                            float(omega), ladder._signs(), Phi, exps, mod)
            out[i] = np.log(mod[-1])
        return out

    print("\nladder (auto's Magnus) against a fine reference; log max|mu| per period, one core")
    print(f"{'model':<18}{'speeds':>7}{'certified':>10}{'ms/speed':>10}{'steps med/max':>15}{'worst true/est':>16}"
          f"{'max true':>10}{'fixed 128':>11}")
    for name, model, w, ref_order, ref_steps in cases:
        spectra = model._power_spectra[:3]
        ladder = MagnusLadder(*spectra)
        reference = growth(ladder, w, ref_steps, ref_order)
        ladder.solve(w[:1], np.inf)  # warm-up
        t0 = time.perf_counter()
        est = ladder.solve(w, np.inf)
        seconds = time.perf_counter() - t0
        top = est.exponents.real.max(axis=1) * 2 * np.pi / w
        true = np.abs(top - reference)
        ok = est.accepted
        fixed = np.abs(growth(ladder, w, 128 if ladder.signs is None else 64, 4) - reference)  # 128 per period
        print(f"{name:<18}{w.size:7d}{ok.sum():10d}{1e3 * seconds / w.size:10.2f}"
              f"{int(np.median(est.steps)):>9d}/{est.steps.max():<5d}{np.max(true[ok] / est.error[ok]):16.2f}"
              f"{true[ok].max():10.1e}{np.nanmax(fixed):11.1e}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--budget", type=float, default=3.0, help="seconds per method and case")
    ap.add_argument("--quick", action="store_true", help="fewer cases")
    ap.add_argument("--sweep", action="store_true", help="also time periodyn.sweep of 1000 speeds")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--per-speed", action="store_true", help="only the stability-alone table per speed")
    ap.add_argument("--errors", action="store_true", help="only the ladder's certified vs true errors")
    ap.add_argument("--large", action="store_true", help="with --errors: also the 32-element slider-crank (minutes)")
    args = ap.parse_args()
    if args.per_speed:
        per_speed()
        return
    if args.errors:
        certified_errors(args.large)
        return
    if args.sweep:
        sweep_rates(args.workers)
    print(f"{'model':<18}{'n':>4}{'m':>4}" + "".join(f"{k:>10}" for k in METHODS)
          + "  best-Hill/auto  best/auto  auto's choices   (speeds/s)")
    cases = [(name, *shipped(name)) for name in ("pendulum", "elliptic_pendulum_elements", "slider_crank",
                                                 "slider_crank_elements")]
    for name, model, omegas, m in cases:
        row(name[:18], model, m, omegas, args.budget)
    if not args.quick:
        w0 = periodyn.examples.pendulum().metadata["omega0"]
        for m in (4, 32):
            row("pendulum", periodyn.examples.pendulum(samples=max(64, 4 * m + 8)), m,
                np.linspace(0.1, 1.4, 200) * w0, args.budget)
    speeds = np.linspace(150.0, 300.0, 200)
    for el in ((2, 4, 8, 16, 32) if not args.quick else (8, 32)):
        for m in ((4, 12, 32, 64) if not args.quick else (12,)):
            row(f"slider-crank x{el}", scaled_slider_crank(el, max(64, 4 * m + 8)), m, speeds, args.budget)


if __name__ == "__main__":
    main()
