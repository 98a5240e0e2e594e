"""Input generators and checks of benchmarks/property_run.py, one pair per kind of input.

A generator draws one case (a plain dict, printable) from a NumPy Generator; its check
runs periodyn on it and returns the number of points flagged as failed, returns None
where the command refused the input with exit code 2, or raises ``Wrong`` where a result
disagrees with the oracle of benchmarks/property_oracles.py (or a broken input was
accepted). InputError / ConvergenceError raised by periodyn count as clean refusals.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from property_oracles import G, Wrong, mathieu_reference

ROOT = Path(__file__).resolve().parents[1]
NAN, INF = float("nan"), float("inf")
#: verdicts are compared where log max|mu| per period is at least this far from 0
MARGIN = 0.02
#: amplitudes agree to this relative error where no multiplier is within 0.05 of 1
AMPLITUDE_RTOL = 0.05


def _wrong(message: str):
    raise Wrong(message)


def toml_value(value) -> str:
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value == INF else "-inf" if value == -INF else repr(value))
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return repr(value)


def _pick(rng, values):
    return values[int(rng.integers(len(values)))]


def check_point(where: str, omega: float, amplitude: float, stable, exponents, params: dict,
                resolved: bool = True) -> None:
    """One solved point of the linearized elliptic pendulum against eq. (29) integrated;
    resolved: False where the HB truncation indicator flags the amplitude."""
    ref = mathieu_reference(omega, **params)
    if stable is not None and abs(ref.log_growth) > MARGIN and bool(stable) != (ref.log_growth < 0):
        _wrong(f"{where}: omega {omega:.6g}: stable={bool(stable)} but log max|mu| = {ref.log_growth:.4g} by the monodromy")
    if resolved and ref.conditioning > 0.05 and abs(amplitude - ref.amplitude[0]) > AMPLITUDE_RTOL * ref.amplitude[0] + 1e-12:
        _wrong(f"{where}: omega {omega:.6g}: amplitude {amplitude:.6g}, integration {ref.amplitude[0]:.6g}")
    if exponents is not None:
        w0 = math.sqrt(G / params["length"])
        total = float(np.sum(np.real(exponents)))
        if abs(total + 2 * params["zeta"] * w0) > 1e-4 * w0:
            _wrong(f"{where}: omega {omega:.6g}: Liouville: sum Re(exponents) = {total:.8g}, "
                   f"-2 zeta w0 = {-2 * params['zeta'] * w0:.8g}")


def check_dataset(where: str, ds, params: dict | None, omega=None) -> int:
    """Every point solved with finite numbers or failed with a reason; solved points
    against the oracle (params: the pendulum's, None: no oracle). Returns failed points."""
    from periodyn.harmonic.truncation import BALANCE_TRUNCATION_TOL
    from periodyn.results import STATUS_FAILED, STATUS_SOLVED

    status = ds["status"].values.reshape(-1)
    if not set(np.unique(status)) <= {STATUS_SOLVED, STATUS_FAILED}:
        _wrong(f"{where}: unknown status values {np.unique(status)}")
    stability = bool(int(ds.attrs.get("stability", 1)))
    names = ("amplitude", "mean", "harmonics", "residual") + (("exponents", "max_real_exponent") if stability else ())
    solved = status == STATUS_SOLVED
    for name in names:
        values = ds[name].values.reshape(status.size, -1)
        if not np.isfinite(values[solved]).all():
            _wrong(f"{where}: {name} not finite at a solved point")
    messages = ds["message"].values.reshape(-1)
    if not all(messages[~solved]):
        _wrong(f"{where}: a failed point without its reason")
    if ds["stable"].values.reshape(-1)[~solved].any():
        _wrong(f"{where}: a failed point called stable")
    if omega is not None and not np.allclose(np.sort(ds["omega"].values), np.sort(omega), rtol=1e-12):
        _wrong(f"{where}: speeds {ds['omega'].values} instead of {np.sort(omega)} rad/s")
    flagged = solved & (ds["balance_truncation"].values.reshape(-1) > BALANCE_TRUNCATION_TOL)
    if params is not None:
        for i in np.flatnonzero(solved):
            check_point(where, float(ds["omega"].values[i]), float(ds["amplitude"].values[i, 0]),
                        ds["stable"].values[i] if stability else None,
                        ds["exponents"].values[i] if stability else None, params, not flagged[i])
    return int((~solved).sum() + flagged.sum())


def ran(path: Path, out: Path, broken: str, extra=()) -> bool:
    """``periodyn sweep path``: False where it refused the input cleanly (exit 2); any other
    failure, or a broken input (``broken``: what is broken, '' for none) accepted, is Wrong."""
    from periodyn.cli import main

    code = main(["sweep", str(path), "--out", str(out), "--workers", "1", "-q", *extra])
    if code == 2:
        return False
    if code != 0:
        _wrong(f"exit code {code}")
    if broken:
        _wrong(f"broken {broken} accepted")
    return True


# ----------------------------------------------------------------------------- sweep files
STABILITY = [True, False, "auto", "dense", "sparse", "monodromy", "magnus"]
BAD_SWEEP = {
    "harmonics": [0, -1, 2.5, "3", True, 100000, NAN], "samples": [0, -1, 2, 200001, "x", 3.5],
    "start": [0.0, -1.0, NAN, INF, "a"], "stop": [0.0, -1.0, NAN, INF, "a"], "num": [0, -1, 10 ** 8, 1.5, "2"],
    "unit": ["furlongs", "omega1", 3], "stability": ["fast", "Dense", 3, NAN],
    "eccentricity": [NAN, "x", INF], "zeta": [-0.01, NAN, "x", INF], "length": [0.0, -1.0, NAN, "x", INF],
    "radius": [0.0, -0.5, "r", NAN],
}
UNITS = {"omega0": None, "Hz": 2 * math.pi, "rad/s": 1.0}


def pendulum_params(rng) -> dict:
    length = float(rng.uniform(0.2, 4.0))
    return {"length": length, "radius": float(rng.uniform(0.05, 1.5)) * length,
            "eccentricity": float(rng.uniform(0.0, 0.9)), "zeta": _pick(rng, [0.0, float(rng.uniform(0.0, 0.3))])}


def sweep_file_case(rng) -> dict:
    params = pendulum_params(rng)
    w0 = math.sqrt(G / params["length"])
    unit = _pick(rng, list(UNITS))
    factor = w0 if unit == "omega0" else UNITS[unit]
    m = int(rng.integers(1, 9))
    v = {**params, "harmonics": m, "unit": unit, "num": int(rng.integers(1, 4)),
         "start": float(rng.uniform(0.1, 1.5)) * w0 / factor, "stop": float(rng.uniform(0.1, 1.5)) * w0 / factor,
         "samples": _pick(rng, [None, int(rng.integers(2 * m + 3, 49))]), "stability": _pick(rng, STABILITY)}
    broken = _pick(rng, [None] * 8 + list(BAD_SWEEP))
    if broken:
        v[broken] = _pick(rng, BAD_SWEEP[broken])
    return {"broken": broken, **v}


def sweep_file_text(v: dict) -> str:
    lines = ["[model]", 'example = "pendulum"', "[model.parameters]"]
    lines += [f"{k} = {toml_value(v[k])}" for k in ("length", "radius", "eccentricity", "zeta")]
    lines += ["[sweep]", f"omega = {{ start = {toml_value(v['start'])}, stop = {toml_value(v['stop'])}, "
                         f"num = {toml_value(v['num'])}, unit = {toml_value(v['unit'])} }}",
              f"harmonics = {toml_value(v['harmonics'])}", f"stability = {toml_value(v['stability'])}"]
    if v["samples"] is not None:
        lines.append(f"samples = {toml_value(v['samples'])}")
    return "\n".join(lines) + "\n"


def sweep_file_check(v: dict, workdir: Path):
    from periodyn.results import load

    path, out = workdir / "s.toml", workdir / "s.nc"
    path.write_text(sweep_file_text(v))
    if not ran(path, out, f"{v['broken']} = {v[v['broken']]!r}" if v["broken"] else ""):
        return None
    w0 = math.sqrt(G / v["length"])
    factor = w0 if v["unit"] == "omega0" else UNITS[v["unit"]]
    params = {k: v[k] for k in ("length", "radius", "eccentricity", "zeta")}
    return check_dataset("sweep file", load(out), params, np.linspace(v["start"], v["stop"], v["num"]) * factor)


# ----------------------------------------------------------------------------- element files
ELEMENTS = (ROOT / "sweeps" / "elliptic_pendulum_elements.toml").read_text()
BAD_ELEMENTS = {
    "self hinge": ('angles = ["pinion_P", "pendulum"]', 'angles = ["pendulum", "pendulum"]'),
    "unknown node": ('angles = ["pinion_P", "pendulum"]', 'angles = ["pinion_P", "pendel"]'),
    "negative damping": ("damping = 0.06264183905346331", "damping = -0.1"),
    "nan damping": ("damping = 0.06264183905346331", "damping = nan"),
    "text damping": ("damping = 0.06264183905346331", 'damping = "some"'),
    "zero mass": ("B = 1.0", "B = 0.0"), "negative mass": ("B = 1.0", "B = -1.0"),
    "zero length": ("B = [0.0, -1.75]", "B at P"), "bad type": ('type = "hinge"', 'type = "spring"'),
    "zero harmonics": ("harmonics = 12", "harmonics = 0"), "few samples": ("samples = 64", "samples = 7"),
    "3-D point": ("B = [0.0, -1.75]", "B = [0.0, -1.75, 0.0]"), "unknown key": ("mode = \"free\"", "mode = \"loose\""),
}


def element_case(rng) -> dict:
    r, e, length = float(rng.uniform(0.1, 1.0)), float(rng.uniform(0.0, 0.9)), float(rng.uniform(0.3, 3.0))
    w0 = math.sqrt(G / length)
    a, b = np.sort(rng.uniform(0.1, 1.4, 2)) * w0
    return {"broken": _pick(rng, [None] * 10 + list(BAD_ELEMENTS)), "r": r, "e": e, "length": length,
            "damping": _pick(rng, [0.0, float(rng.uniform(0.0, 0.5))]), "mass": float(rng.uniform(0.2, 5.0)),
            "harmonics": int(rng.integers(6, 15)), "omega": (float(a), float(b), int(rng.integers(1, 4)))}


def element_check(v: dict, workdir: Path):
    from periodyn.results import load

    text = ELEMENTS
    if v["broken"] and v["broken"] != "zero length":
        old, new = BAD_ELEMENTS[v["broken"]]
        assert old in text, old
        text = text.replace(old, new, 1)
    r, e, length = v["r"], v["e"], v["length"]
    for old, new in (("C = [0.0, -0.5]", f"C = [0.0, {-r!r}]"), ("P = [0.0, -0.75]", f"P = [0.0, {-(r + e * r)!r}]"),
                     ("B = [0.0, -1.75]", f"B = [0.0, {-(r + e * r + length)!r}]"),
                     ("damping = 0.06264183905346331", f"damping = {v['damping']!r}"), ("B = 1.0", f"B = {v['mass']!r}"),
                     ("harmonics = 12", f"harmonics = {v['harmonics']}")):
        text = text.replace(old, new, 1)
    if v["broken"] == "zero length":  # B onto P, wherever P is now
        text = text.replace(f"B = [0.0, {-(r + e * r + length)!r}]", f"B = [0.0, {-(r + e * r)!r}]")
    path, out = workdir / "e.toml", workdir / "e.nc"
    path.write_text(text)
    a, b, n = v["omega"]
    if not ran(path, out, f"element file ({v['broken']})" if v["broken"] else "", ["--omega", f"{a!r}:{b!r}:{n}"]):
        return None
    w0 = math.sqrt(G / length)
    params = {"length": length, "radius": r, "eccentricity": e, "zeta": v["damping"] / (2 * w0 * v["mass"] * length ** 2)}
    return check_dataset("element file", load(out), params, np.linspace(a, b, n))


# ----------------------------------------------------------------------------- rotor files
IMPERIAL = {"length": 0.0254, "mass": 0.45359237, "force": 4.4482216}
BAD_ROTOR = [("kyy = ", 'kyy = "stiff"'), ("length = ", "length = 0"), ("E = ", "E = -1.0"),
             ("elements = ", "elements = 0"), ("elements = ", "elements = 2.5"), ("density = ", "density = true"),
             ("outer_diameter = ", "outer_diameter = 0.0"), ("[material]", "[material]\nfoo = 1"),
             ("at = ", "at = nan"), ("end = ", "end = -5.0"), ("mass = ", "mass = -1.0"), ("czz = ", "czz = -2.0"),
             ("binary", ""), ("[units]", "[unit]"), ("disk at", "")]


def rotor_case(rng) -> dict:
    units = _pick(rng, [None, IMPERIAL])
    length = float(rng.uniform(0.3, 2.0))
    sections = int(rng.integers(1, 3))
    elements = [int(rng.integers(1, 4)) for _ in range(sections)]
    damping = _pick(rng, [0.0, float(10 ** rng.uniform(1, 4))])
    disk = _pick(rng, [None, {"mass": float(rng.uniform(1, 50)), "polar": float(rng.uniform(0.01, 1.0))}])
    return {"broken": _pick(rng, [None] * 12 + [b for b, _ in BAD_ROTOR]), "units": units, "length": length,
            "sections": sections, "elements": elements, "diameter": float(rng.uniform(0.02, 0.1)),
            "E": float(rng.uniform(1e11, 2.2e11)), "density": float(rng.uniform(2000, 8000)),
            "stiffness": float(10 ** rng.uniform(5, 8)), "damping": damping, "disk": disk,
            "speeds": sorted(float(s) for s in rng.uniform(0, 3000, 3))}


def rotor_text(v: dict) -> str:
    L, m, f = (1.0, 1.0, 1.0) if v["units"] is None else (v["units"]["length"], v["units"]["mass"], v["units"]["force"])
    ends = np.linspace(0.0, v["length"], v["sections"] + 1)
    lines = ['[rotor]', 'name = "fuzz"']
    if v["units"]:
        lines += ["[units]", f"length = {float(L)!r}", f"mass = {float(m)!r}", f"force = {float(f)!r}"]
    lines += ["[material]", f"E = {float(v['E'] / (f / L ** 2))!r}", f"density = {float(v['density'] / (m / L ** 3))!r}"]
    for a, b, n in zip(ends, ends[1:], v["elements"]):
        lines += ["[[shaft]]", f"start = {float(a / L)!r}", f"end = {float(b / L)!r}", f"outer_diameter = {float(v['diameter'] / L)!r}",
                  f"elements = {n}"]
    for at in (0.0, v["length"]):
        k, c = v["stiffness"] / (f / L), v["damping"] / (f / L)
        lines += ["[[bearing]]", f"at = {float(at / L)!r}", f"kyy = {float(k)!r}", f"kzz = {float(k)!r}", f"cyy = {float(c)!r}", f"czz = {float(c)!r}"]
    if v["disk"]:
        d = v["disk"]
        lines += ["[[disk]]", f"at = {float(v['length'] / L)!r}", f"mass = {float(d['mass'] / (f / L))!r}",
                  f"polar = {float(d['polar'] / (f * L))!r}", f"diametral = {float(0.5 * d['polar'] / (f * L))!r}"]
    return "\n".join(lines) + "\n"


def python_rotor(v: dict):
    """The same rotor through the Python builder, in SI units."""
    from periodyn.rotor import Bearing, Rotor

    r = Rotor("fuzz")
    ends = np.linspace(0.0, v["length"], v["sections"] + 1)
    for a, b, n in zip(ends, ends[1:], v["elements"]):
        r.add_shaft(a, b, outer_diameter=v["diameter"], E=v["E"], density=v["density"], elements=n)
    for at in (0.0, v["length"]):
        r.add_bearing(Bearing(at, v["stiffness"], v["stiffness"], cyy=v["damping"], czz=v["damping"]))
    if v["disk"]:
        r.add_disk(v["length"], v["disk"]["mass"], v["disk"]["polar"], 0.5 * v["disk"]["polar"])
    return r.compile()


def rotor_check(v: dict, workdir: Path):
    from periodyn.rotor import campbell, load_rotor

    path = workdir / "r.toml"
    text = rotor_text(v)
    broken = next((b for b in BAD_ROTOR if b[0] == v["broken"]), None)
    if v["broken"] == "binary":
        path.write_bytes(bytes(range(256)) * 4)
    else:
        if v["broken"] == "disk at":   # at 0.37 of the length: never a station of these meshes
            at = 0.37 * v["length"] / (v["units"] or {"length": 1.0})["length"]
            text += f"[[disk]]\nat = {at!r}\nmass = 1.0\npolar = 0.1\ndiametral = 0.05\n"
        elif broken:
            lines = text.splitlines()
            i = next((i for i, line in enumerate(lines) if line.startswith(broken[0])), None)
            if i is None:                         # a rotor without the key: break the first bearing instead
                lines.append("[[bearing]]\nat = 0.0\nkyy = -1.0\nkzz = 1.0")
            else:
                lines[i] = broken[1]
            text = "\n".join(lines) + "\n"
        path.write_text(text)
    model = load_rotor(path)
    if v["broken"]:
        _wrong(f"broken rotor file ({v['broken']}) accepted")
    from_file = campbell(model, v["speeds"])["eigenvalue"].values
    built = campbell(python_rotor(v), v["speeds"])["eigenvalue"].values
    if from_file.shape != built.shape or not np.allclose(from_file, built, rtol=1e-8, atol=1e-8):
        _wrong("rotor file and Python builder give different eigenvalues")
    scale = np.abs(from_file).max(axis=1, keepdims=True)
    if v["damping"] > 0 and (from_file.real > 1e-9 * scale).any():
        _wrong(f"a growing mode with bearing damping: max Re {from_file.real.max():.3g} 1/s")
    if v["damping"] == 0 and (np.abs(from_file.real) > 1e-7 * scale).any():
        _wrong(f"a damped mode without damping: max |Re| {np.abs(from_file.real).max():.3g} 1/s")
    return 0


KINDS = {"sweep files": (sweep_file_case, sweep_file_check), "element files": (element_case, element_check),
         "rotor files": (rotor_case, rotor_check)}
