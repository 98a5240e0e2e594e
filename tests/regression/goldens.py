"""Golden regression values: small, exactly reproducible results of every paper example whose
change must be reviewed (compared at rtol 1e-8 by ``test_goldens.py``). Regenerate after an
intended change, from the project root, with

    PYTHONPATH=src python -m tests.regression.goldens              # every case
    PYTHONPATH=src python -m tests.regression.goldens cardan_zone_edges rotor_campbell   # some

and review the diff of tests/regression/golden/*.json before committing.

Each case is a function returning a JSON-able dict of lists (strings and booleans are compared
exactly, numbers at rtol 1e-8); each runs in a few seconds once the kernels are compiled:

==========================  =====================================================================
case                        what it pins
==========================  =====================================================================
pendulum_sweep(_auto)       linearized pendulum (Schwab & Meijaard 2001, eq. 29), 15 speeds
cardan_zone_edges           Cardan shaft (section 4.4): the four edges of its two unstable zones,
                            their crossing type and side (m = 4, 32 samples, dense Hill)
slider_crank_sweep          slider-crank with flexible rod (section 4.2): output amplitudes and
                            max Re exponent at 5 speeds in 150-280 rad/s (m = 12, dense Hill)
rotor_campbell              Table I rotor (section 4.3): the 8 lowest eigenvalues, whirl and the
                            largest real part at 5 speeds 1000-8000 rpm
rod_pendulum_branch         rod pendulum (Ju et al. 2021, eqs. 61-62, the parameters of
                            sweeps/dae_rod_pendulum.toml): IHB branch (H = 10) with its folds
slider_chain_ihb            slider with a chain of 3 rods (eqs. 70-82): IHB orbits (H = 6) and
                            their largest multiplier at 3 speeds
==========================  =====================================================================
"""

from __future__ import annotations

import json
import pathlib
import sys
import warnings

import numpy as np

import periodyn
from periodyn.speeds import SpeedSolver
from periodyn.stability.floquet import TruncationWarning

GOLDEN = pathlib.Path(__file__).parent / "golden"


def pendulum_sweep(method: str = "dense") -> dict:
    """Linearized pendulum (eq. 29): amplitude, mean, max Re exponent at 15 speeds, m = 12,
    stability by dense Hill (or ``method``)."""
    model = periodyn.examples.pendulum(samples=64)
    r = np.linspace(0.1, 1.4, 15)
    solver = SpeedSolver(model, 12, stability=method)
    points = [solver.solve(x * model.metadata["omega0"]) for x in r]
    out = {"omega_over_omega0": r.tolist(), "amplitude": [float(p.amplitude[0]) for p in points],
           "mean": [float(p.mean[0]) for p in points], "max_real": [p.max_real for p in points]}
    if method == "auto":
        out["method"] = [p.method for p in points]
    return out


def pendulum_sweep_auto() -> dict:
    """:func:`pendulum_sweep` with the default stability method, and what it chose."""
    return pendulum_sweep("auto")


def cardan_zone_edges() -> dict:
    """Cardan shaft at alpha = pi/6, 1 % damping, 32 samples: the four stability boundaries of
    the zones 0.65-0.68 and 0.78-0.92 omega_b (dense Hill, m = 4), each bracketed by two grid
    speeds 0.005-0.01 omega_b apart and refined by Brent's method to 1e-11 (relative), with
    the type of the crossing and the stable side (the same edges and types as m = 6 and 12; at
    m = 4 Hill's edge energy is up to 2e-3, above the truncation tolerance, hence
    truncation="warn")."""
    from periodyn.stability.boundaries import stability_boundaries

    model = periodyn.examples.cardan_shaft(samples=32)
    wb = model.metadata["omega_b"]
    grid = np.array([0.64, 0.65, 0.675, 0.685, 0.78, 0.79, 0.91, 0.92])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TruncationWarning)
        found = stability_boundaries(model.at, grid * wb, 4, stability="dense", xtol=1e-11, truncation="warn")
    return {"omega_b": [wb], "grid": grid.tolist(), "omega_over_omega_b": [b.omega / wb for b in found],
            "kind": [b.kind for b in found], "becomes_stable": [b.becomes_stable for b in found]}


def slider_crank_sweep() -> dict:
    """Slider-crank, 2 % damping, 64 samples: amplitude of every output and max Re exponent
    (dense Hill, m = 12) at 150 rad/s (Fig. 4), near the 1/5, 1/4 and 1/3 resonances and between."""
    model = periodyn.examples.slider_crank(0.02, 64)
    omega = [150.0, 166.0, 200.0, 250.0, 280.0]
    solver = SpeedSolver(model, 12, stability="dense")
    points = [solver.solve(w) for w in omega]
    return {"omega": omega, "output_names": list(points[0].output_names),
            "amplitude": [p.amplitude.tolist() for p in points], "max_real": [p.max_real for p in points]}


def rotor_campbell() -> dict:
    """Table I rotor (5 elements): the 8 lowest modes at 1000-8000 rpm, stationary-frame
    eigenvalues, whirl directions, the largest real part of all modes, the threshold speed."""
    from periodyn.rotor import campbell

    rpm = np.array([1000.0, 2000.0, 4000.0, 6000.0, 8000.0])
    ds = campbell(periodyn.examples.rotor(), rpm * np.pi / 30, modes=8)
    lam = ds["eigenvalue"].values
    return {"speed_rpm": rpm.tolist(), "eigenvalue_real": lam.real.tolist(), "eigenvalue_imag": lam.imag.tolist(),
            "whirl": ds["whirl"].values.tolist(), "max_real_eigenvalue": ds["max_real_eigenvalue"].values.tolist(),
            "threshold_speed": [float(ds.attrs["threshold_speed"])]}


def rod_pendulum_branch() -> dict:
    """Rod pendulum with the study's parameters: IHB (H = 10) response curve over 2.5-5 rad/s
    (largest step 0.1, Magnus stability): every point's omega, swing amplitude, largest
    multiplier, and the special points (type, index, omega, swing amplitude)."""
    from periodyn.arclength import continuation

    br = continuation(periodyn.examples.rod_pendulum(), (2.5, 5.0), harmonics=10, ds_max=0.1, stability="magnus")
    phi = br.solutions[0].coordinate_names.index("phi_rod")
    sp = br.special_points
    return {"omega": [float(w) for w in br.omega], "amplitude_phi": [float(s.amplitude()[phi]) for s in br.solutions],
            "max_multiplier": [s.max_multiplier for s in br.solutions],
            "special_type": [p.type for p in sp], "special_index": [p.index for p in sp],
            "special_omega": [p.omega for p in sp], "special_amplitude_phi": [float(p.amplitude[phi]) for p in sp]}


def slider_chain_ihb() -> dict:
    """Slider with 3 rods (the example's other parameters): IHB (H = 6) orbits solved from the
    hanging chain at 6, 7 and 8 rad/s: amplitude of the slider and of each rod's angle, the
    largest Floquet multiplier (Magnus)."""
    from periodyn.nonlinear import ihb

    system = periodyn.examples.slider_chain_pendulum(n_rods=3)
    omega = [6.0, 7.0, 8.0]
    sols = [ihb(system, w, 6) for w in omega]
    names = sols[0].coordinate_names
    keep = [i for i, n in enumerate(names) if n.startswith("phi_") or n == "x_slider"]
    return {"omega": omega, "coordinates": [names[i] for i in keep],
            "amplitude": [s.amplitude()[keep].tolist() for s in sols],
            "max_multiplier": [s.max_multiplier for s in sols]}


CASES = {"pendulum_sweep": pendulum_sweep, "pendulum_sweep_auto": pendulum_sweep_auto,
         "cardan_zone_edges": cardan_zone_edges, "slider_crank_sweep": slider_crank_sweep,
         "rotor_campbell": rotor_campbell, "rod_pendulum_branch": rod_pendulum_branch,
         "slider_chain_ihb": slider_chain_ihb}


def main(argv=None) -> None:
    names = list(sys.argv[1:] if argv is None else argv) or list(CASES)
    unknown = sorted(set(names) - set(CASES))
    if unknown:
        raise SystemExit(f"unknown cases {unknown}; known: {sorted(CASES)}")
    GOLDEN.mkdir(exist_ok=True)
    for name in names:
        (GOLDEN / f"{name}.json").write_text(json.dumps(CASES[name](), indent=1) + "\n")
        print(f"wrote {GOLDEN / name}.json")


if __name__ == "__main__":
    main()
