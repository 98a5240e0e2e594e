"""DAE builders and API arguments for benchmarks/property_run.py (see property_inputs.py
for the contract of a generator and its check)."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

from property_inputs import MARGIN, check_dataset, pendulum_params
from property_oracles import G, Wrong, liouville_product, linear_reference

BAD_ANY = [float("nan"), float("inf"), "x", True, None, 1j]

# ----------------------------------------------------------------------------- DAE builders
#: builder -> {argument: (low, high, rule)}, rule "pos" (> 0), "nonneg" (>= 0) or "finite"
BUILDERS = {
    "rod_pendulum": {"m1": (0.5, 2.0, "pos"), "l": (0.5, 2.0, "pos"), "eps1": (0.01, 0.2, "nonneg"),
                     "f": (0.01, 0.2, "finite"), "g": (9.0, 10.0, "nonneg")},
    "duffing": {"zeta": (0.02, 0.3, "nonneg"), "alpha": (0.0, 1.0, "finite"), "F": (0.01, 0.1, "finite"),
                "omega0": (0.5, 3.0, "pos")},
    "pendulum_nonlinear": {"length": (0.5, 2.0, "pos"), "radius": (0.005, 0.05, "pos"),
                           "eccentricity": (0.0, 0.9, "finite"), "zeta": (0.01, 0.2, "nonneg")},
    "slider_rod_pendulum": {"m1": (0.7, 1.3, "pos"), "m2": (0.3, 0.7, "pos"), "l": (0.3, 0.7, "pos"),
                            "k1": (70.0, 130.0, "nonneg"), "c1": (0.3, 0.7, "nonneg"), "f": (0.1, 1.0, "finite")},
    "slider_chain_pendulum": {"n_rods": (1, 3, "count"), "m1": (0.7, 1.3, "pos"), "p": (0.1, 1.0, "finite")},
    "inverted_pendulum": {"m1": (0.7, 1.3, "pos"), "l": (0.7, 1.3, "pos"), "kappa": (15.0, 25.0, "pos"),
                          "eps": (0.03, 0.1, "nonneg"), "p": (0.01, 0.05, "finite")},
}


def _speed(name: str, k: dict, rng) -> float:
    """A driving speed (rad/s) around the builder's first natural frequency."""
    if name == "rod_pendulum":
        return float(rng.uniform(0.3, 1.5)) * math.sqrt(1.5 * k["g"] / k["l"])
    if name == "duffing":
        return float(rng.uniform(0.3, 2.0)) * k["omega0"]
    if name == "pendulum_nonlinear":
        return float(rng.uniform(0.2, 0.8)) * math.sqrt(G / k["length"])
    return float(rng.uniform(2.0, 8.0))


def _trace(name: str, k: dict) -> float | None:
    """Constant trace of the flow's Jacobian in the independent coordinates (Liouville),
    None where it depends on the configuration."""
    if name == "rod_pendulum":
        return -3.0 * k["eps1"] / (k["m1"] * k["l"] ** 2)     # pin inertia m l^2 / 3
    if name == "duffing":
        return -2.0 * k["zeta"] * k["omega0"]
    if name == "pendulum_nonlinear":
        return -2.0 * k["zeta"] * math.sqrt(G / k["length"])
    return None


def dae_case(rng) -> dict:
    name = list(BUILDERS)[int(rng.integers(len(BUILDERS)))]
    spec = BUILDERS[name]
    k = {a: int(rng.integers(lo, hi + 1)) if rule == "count" else float(rng.uniform(lo, hi))
         for a, (lo, hi, rule) in spec.items()}
    broken = list(spec)[int(rng.integers(len(spec)))] if rng.random() < 0.4 else None
    if broken:
        rule = spec[broken][2]
        bad = BAD_ANY + {"pos": [0.0, -1.0], "nonneg": [-0.5], "count": [0, -2, 2.5], "finite": []}[rule]
        k[broken] = bad[int(rng.integers(len(bad)))]
    return {"builder": name, "kwargs": k, "broken": broken, "omega": _speed(name, k, rng) if not broken else 1.0,
            "harmonics": int(rng.integers(5, 11))}


def dae_check(v: dict, workdir: Path):
    import periodyn
    from periodyn import examples

    dae = getattr(examples, v["builder"])(**v["kwargs"])
    if v["broken"]:
        raise Wrong(f"{v['builder']}({v['broken']}={v['kwargs'][v['broken']]!r}) accepted")
    w = v["omega"]
    h = periodyn.ihb(dae, w, v["harmonics"])
    s = periodyn.shooting(dae, w, initial=h)             # the IHB orbit must be an orbit of the DAE
    scale = float(np.abs(s.amplitude()).max())
    if np.abs(h.amplitude() - s.amplitude()).max() > 1e-3 * scale + 1e-9:
        raise Wrong(f"IHB amplitude {h.amplitude()} against shooting from it {s.amplitude()}")
    growth = float(np.log(np.abs(s.multipliers).max()))
    if abs(growth) > MARGIN and h.stable != s.stable:
        raise Wrong(f"IHB stable={h.stable}, shooting log max|mu| = {growth:.4g}")
    trace = _trace(v["builder"], v["kwargs"])
    if trace is not None:
        product, expected = abs(np.prod(s.multipliers)), liouville_product(trace, 2 * np.pi / w)
        if abs(product - expected) > 1e-6 * max(1.0, expected):
            raise Wrong(f"Liouville: product of the multipliers {product:.10g}, exp(tr A T) = {expected:.10g}")
    return 0


# ----------------------------------------------------------------------------- API arguments
def rheo_case(rng) -> dict:
    n = int(rng.integers(1, 3))
    m_diag = rng.uniform(0.5, 2.0, n)
    K0 = np.diag(rng.uniform(1.0, 10.0, n)) + (0.3 * rng.standard_normal((n, n)) if n > 1 else 0)
    K0 = 0.5 * (K0 + K0.T)
    C0 = np.diag(rng.uniform(0.0, 0.5, n))
    wn = math.sqrt(float(np.min(np.linalg.eigvalsh(K0)) / m_diag.max()))
    m = int(rng.integers(1, 11))
    return {"n": n, "harmonics": m, "samples": int(rng.integers(2 * m + 5, 2 * m + 17)), "M": m_diag.tolist(), "K0": K0.tolist(), "K1": (rng.uniform(-1, 1, (n, n)) * 3).tolist(),
            "K2": (rng.uniform(-1, 1, (n, n))).tolist(), "C0": C0.tolist(),
            "C1": (rng.uniform(-1, 1, (n, n)) * 0.1).tolist(), "f": rng.uniform(-1, 1, (2, n)).tolist(),
            "omega": float(rng.uniform(0.3, 3.0)) * wn, "harmonics": int(rng.integers(1, 11)),
            "method": ["dense", "sparse", "hill", "monodromy", "magnus", "auto"][int(rng.integers(6))],
            "broken": ([None] * 6 + ["complex M", "nan K", "no samples", "short C", "omega", "harmonics", "method",
                                     "truncation"])[int(rng.integers(14))]}


def rheo_functions(v: dict):
    K0, K1, K2, C0, C1 = (np.array(v[k]) for k in ("K0", "K1", "K2", "C0", "C1"))
    f = np.array(v["f"])
    return (np.diag(v["M"]), lambda th: C0 + C1 * np.cos(th), lambda th: K0 + K1 * np.cos(th) + K2 * np.sin(2 * th),
            lambda th: f[0] * np.sin(th) + f[1] * np.cos(2 * th))


def rheo_check(v: dict, workdir: Path):
    import periodyn
    from periodyn.harmonic.truncation import BalanceTruncationWarning

    M, C, K, f = rheo_functions(v)
    th = 2 * np.pi * np.arange(v["samples"]) / v["samples"]
    Ms = np.repeat(M[None], th.size, 0)
    Cs, Ks, fs = (np.array([g(t) for t in th]) for g in (C, K, f))
    omega, m, method, truncation = v["omega"], v["harmonics"], v["method"], "refuse"
    broken = v["broken"]
    if broken == "complex M":
        Ms = Ms + 1e-3j
    elif broken == "nan K":
        Ks[0, 0, 0] = np.nan
    elif broken == "no samples":
        Ms, Cs, Ks, fs = Ms[:0], Cs[:0], Ks[:0], fs[:0]
    elif broken == "short C":
        Cs = Cs[:-1]
    elif broken == "omega":
        omega = [-1.0, 0.0, float("nan"), "fast", None][v["samples"] % 5]
    elif broken == "harmonics":
        m = [0, -1, 2.5, "3", None, True][v["samples"] % 6]
    elif broken == "method":
        method = ["bogus", None, 3][v["samples"] % 3]
    elif broken == "truncation":
        truncation = ["maybe", None][v["samples"] % 2]
    system = periodyn.RheoLinear.from_samples(Ms, Cs, Ks, fs, omega)
    exps = periodyn.characteristic_exponents(system, m, method, truncation=truncation)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        solution = periodyn.periodic_solution(system, m)
    unresolved = any(issubclass(c.category, BalanceTruncationWarning) for c in caught)
    if broken:
        raise Wrong(f"broken {broken} accepted")
    ref = linear_reference(M, C, K, f, omega)
    if abs(ref.log_growth) > MARGIN and exps.stable != (ref.log_growth < 0):
        raise Wrong(f"stable={exps.stable} ({exps.method}), monodromy log max|mu| = {ref.log_growth:.4g}")
    trace = -float(np.trace(np.linalg.solve(M, np.array(v["C0"]))))   # mean of -tr(M^-1 C(t))
    total = float(np.sum(np.real(exps.exponents)))
    if abs(total - trace) > 1e-4 * max(1.0, abs(omega)):
        raise Wrong(f"Liouville: sum Re(exponents) {total:.8g} ({exps.method}), mean trace {trace:.8g}")
    amp = solution.amplitude()
    if not unresolved and ref.conditioning > 0.05 and np.abs(amp - ref.amplitude).max() > 0.05 * ref.amplitude.max() + 1e-12:
        raise Wrong(f"amplitude {amp} against integration {ref.amplitude}")
    return int(unresolved)


def sweep_call_check(v: dict, workdir: Path):
    import periodyn
    from periodyn.examples import pendulum

    model = pendulum(samples=v["samples"], **v["params"])
    ds = periodyn.sweep(model, v["omega"], v["harmonics"], stability=v["stability"], progress=False)
    if v["broken"]:
        raise Wrong(f"sweep accepted {v['broken']}")
    return check_dataset("sweep()", ds, v["params"], np.atleast_1d(v["omega"]))


def sweep_call_case(rng) -> dict:
    params = pendulum_params(rng)
    w0 = math.sqrt(G / params["length"])
    v = {"params": params, "omega": (rng.uniform(0.1, 1.5, int(rng.integers(1, 4))) * w0).tolist(),
         "harmonics": int(rng.integers(1, 9)), "samples": int(rng.integers(24, 49)),
         "stability": ["auto", "dense", "sparse", "monodromy", "magnus", True, False][int(rng.integers(7))],
         "broken": ([None] * 4 + ["omega", "harmonics", "stability"])[int(rng.integers(7))]}
    if v["broken"] == "omega":
        v["omega"] = [[], [-1.0], [float("nan")], "fast", [[1.0, 2.0]], None, [w0, 0.0]][int(rng.integers(7))]
    elif v["broken"] == "harmonics":
        v["harmonics"] = [0, -2, 2.5, "4", None, 10 ** 6][int(rng.integers(6))]
    elif v["broken"] == "stability":
        v["stability"] = ["fast", 3, None, "Dense"][int(rng.integers(4))]
    return v


def campbell_case(rng) -> dict:
    good = sorted(rng.uniform(0, 3000, 3).tolist())
    broken = [None] * 3 + ["speeds", "modes", "frame", "eigensolver"]
    return {"speeds": good, "modes": int(rng.integers(1, 9)), "frame": "auto", "eigensolver": "auto",
            "broken": broken[int(rng.integers(len(broken)))], "pick": int(rng.integers(6))}


def campbell_check(v: dict, workdir: Path):
    import periodyn
    from periodyn.rotor import Bearing, Rotor

    r = Rotor("shaft")
    r.add_shaft(0.0, 1.0, outer_diameter=0.05, E=2e11, density=7800.0, elements=4)
    for at in (0.0, 1.0):
        r.add_bearing(Bearing(at, 1e6, 1e6, cyy=100.0, czz=100.0))
    kw = {k: v[k] for k in ("speeds", "modes", "frame", "eigensolver")}
    bad = {"speeds": ["fast", [-1.0], [float("nan")], [], [[1.0, 2.0]], None], "modes": [0, 100, "2", 2.5, -1, True],
           "frame": ["inertial", 3, None, "x", "", "ROTATING"], "eigensolver": ["fast", 3, None, "x", "", "Dense"]}
    if v["broken"]:
        kw[v["broken"]] = bad[v["broken"]][v["pick"]]
    ds = periodyn.campbell(r.compile(), **kw)
    if v["broken"]:
        raise Wrong(f"campbell accepted {v['broken']}={kw[v['broken']]!r}")
    lam = ds["eigenvalue"].values
    if (lam.real > 1e-9 * np.abs(lam).max()).any():
        raise Wrong(f"a growing mode with bearing damping: max Re {lam.real.max():.3g}")
    return 0


def range_case(rng) -> dict:
    return {"omega": [(1.0, 1.0), (1.0, float("inf")), (float("nan"), 2.0), (-1.0, 2.0), "x", (1.0,), None,
                      (0.0, 2.0), (1.0, 2.0, 3.0), ("a", 2.0)][int(rng.integers(10))]}


def range_check(v: dict, workdir: Path):
    import periodyn
    from periodyn.examples import duffing

    periodyn.continuation(duffing(), omega=v["omega"])
    raise Wrong(f"continuation accepted omega={v['omega']!r}")


API = [(rheo_case, rheo_check, 0.45), (sweep_call_case, sweep_call_check, 0.3), (campbell_case, campbell_check, 0.15),
       (range_case, range_check, 0.1)]


def api_case(rng) -> dict:
    i = int(rng.choice(len(API), p=[w for *_, w in API]))
    return {"call": API[i][1].__name__, **API[i][0](rng)}


def api_check(v: dict, workdir: Path):
    return next(check for _, check, _ in API if check.__name__ == v["call"])(v, workdir)


KINDS = {"DAE builders": (dae_case, dae_check), "API arguments": (api_case, api_check)}
