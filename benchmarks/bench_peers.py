"""periodyn next to pyHarm on small and mid-size non-linear frequency responses: NLvib's
Duffing example 01 (m = 1, c = 0.05, k = 1, knl = 0.1, F = 0.18, Omega 0.5-1.6, H = 7) and
cubic chains of 10 and 40 masses (each mass grounded by k = 1, c = 0.05 and a cubic spring
knl = 0.1, neighbours coupled by k = 1, F = 0.18 cos(Omega t) on the first mass; Omega
0.5-1.6, H = 10). Per curve: points, wall and CPU seconds, CPU per point, folds; periodyn with
stability (the continuation default) and without, side by side in one run (one BLAS/Numba
thread, warm: every curve is traced once before it is timed, best of --rounds; pyHarm's 40-mass
chain once). The summary gives each on / off ratio of wall and of CPU seconds (the CPU ratio
is the one other load on the machine does not move).

pyHarm (pip package pyharm-os) is optional: imported when it is installed, or run by another
interpreter that has it (--pyharm-python /path/to/python: the pyHarm rows come from that
process, same machine and thread settings); without either its rows are skipped with a note.
pyHarm's curve: its own arc-length defaults (tangent predictor, arc-length corrector) with
ds0 = 0.02, ds_max = 0.1, 64 time samples (nti); its folds are its points where omega turns
back (it does not refine them), periodyn's are refined (dp/ds = 0 on the arc).

Run: python benchmarks/bench_peers.py [--rounds 3] [--skip-40] [--pyharm-python PATH]
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[var] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

OMEGA = (0.5, 1.6)


def duffing():
    """NLvib example 01 as a vectorized periodyn.DAE (analytic Jacobian)."""
    import periodyn

    def force(q, qd, t, w):
        return -0.05 * qd - q - 0.1 * q ** 3 + 0.18 * np.cos(w * t)[:, None]

    def jac(q, qd, t, w):
        return (-1.0 - 0.3 * q ** 2)[:, :, None], np.full((len(t), 1, 1), -0.05)

    return periodyn.DAE(np.eye(1), force, force_jacobian=jac, vectorized=True, name="duffing")


def chain(n: int):
    """n-mass cubic chain (module docstring) as a vectorized periodyn.DAE (analytic Jacobian)."""
    import periodyn

    _, K, C = chain_matrices(n)
    e0 = np.zeros(n)
    e0[0] = 0.18

    def force(q, qd, t, w):
        return -qd @ C.T - q @ K.T - 0.1 * q ** 3 + np.cos(w * t)[:, None] * e0

    def jac(q, qd, t, w):
        Kq = np.broadcast_to(-K, (len(t), n, n)).copy()
        Kq[:, np.arange(n), np.arange(n)] -= 0.3 * q ** 2
        return Kq, np.broadcast_to(-C, (len(t), n, n))

    return periodyn.DAE(np.eye(n), force, force_jacobian=jac, vectorized=True, name=f"chain{n}")


def timed(call, rounds):
    """(best wall s, CPU s of that round, result)."""
    best = (np.inf, np.inf, None)
    for _ in range(rounds):
        w0, c0 = time.perf_counter(), time.process_time()
        out = call()
        w, c = time.perf_counter() - w0, time.process_time() - c0
        if w < best[0]:
            best = (w, c, out)
    return best


def row(label, wall, cpu, points, folds):
    fl = ", ".join(f"{f:.6f}" for f in sorted(folds, reverse=True)) or "-"
    print(f"{label:<44} {points:6d} {wall:9.3f} {cpu:9.3f} {1e3 * cpu / max(points, 1):9.2f}  {fl}")


def periodyn_rows(name, system, H, rounds):
    from periodyn.arclength import continuation
    out = {}
    for stab, label in (("default", "stability on"), (None, "stability off")):
        kw = {} if stab == "default" else {"stability": None}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            continuation(system, OMEGA, harmonics=H, **kw)  # warm
            wall, cpu, br = timed(lambda: continuation(system, OMEGA, harmonics=H, **kw), rounds)
        row(f"periodyn {name} H={H}, {label}", wall, cpu, len(br), [p.omega for p in br.points("fold")])
        out[label] = wall
        out[label + " cpu"] = cpu
    return out


def chain_matrices(n: int):
    """M, K (ground k = 1 plus couplings k = 1: the end masses have one neighbour), C."""
    K = 3.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[0, 0] = K[-1, -1] = 2.0
    return np.eye(n), K, 0.05 * np.eye(n)


def pyharm_input(n: int, H: int) -> dict:
    """pyHarm input: a matrix substructure (M, K, C), a cubic spring to ground at every mass, the
    cosine force on the first (Duffing: n = 1, K = 1)."""
    M, K, C = (np.eye(1), np.eye(1), 0.05 * np.eye(1)) if n == 1 else chain_matrices(n)
    con = {f"cub{i}": {"type": "CubicSpring", "connect": {"sub": [i]}, "dirs": [0], "k": 0.1} for i in range(n)}
    con["force"] = {"type": "CosinusForcing", "connect": {"sub": [0]}, "dirs": [0], "amp": 0.18}
    return {"system": {"type": "Base", "nh": H, "nti": 64 if H <= 7 else 128},
            "substructures": {"sub": {"type": "substructure", "ndofs": 1, "matrix": {"M": M, "K": K, "C": C}}},
            "connectors": con,
            "analysis": {"FRF": {"study": "frf", "puls_inf": OMEGA[0], "puls_sup": OMEGA[1], "ds0": 0.02,
                                 "ds_max": 0.1, "verbose": False}}}


def pyharm_curve(n: int, H: int, rounds: int) -> dict:
    """{points, wall, cpu, folds} of pyHarm's curve (this process must import pyHarm)."""
    import logging

    os.chdir(tempfile.mkdtemp(prefix="pyharm-"))  # its import writes a context folder into the working directory
    import pyHarm
    logging.disable(logging.CRITICAL)

    def run():
        maestro = pyHarm.Maestro(pyharm_input(n, H))
        maestro.operate()
        return maestro.nls["FRF"].SolList

    run()  # warm (Numba compilation)
    wall, cpu, sols = timed(run, rounds)
    om = np.array([s.x[-1] for s in sols])
    turns = np.nonzero(np.diff(np.sign(np.diff(om))))[0] + 1
    return {"points": len(sols), "wall": wall, "cpu": cpu, "folds": [float(om[i]) for i in turns]}


def pyharm_rows(name, n, H, rounds, python):
    try:
        if python:
            out = subprocess.run([python, __file__, "--pyharm-only", str(n), str(H), str(rounds)],
                                 capture_output=True, text=True, check=True).stdout
            res = json.loads(out.strip().splitlines()[-1])
        else:
            res = pyharm_curve(n, H, rounds)
    except ImportError:
        print(f"pyHarm {name}: pyHarm not installed, skipped (pip install pyharm-os, or --pyharm-python)")
        return None
    row(f"pyHarm {name} H={H}, no stability", res["wall"], res["cpu"], res["points"], res["folds"])
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--skip-40", action="store_true", help="leave out the 40-mass chain (slowest)")
    ap.add_argument("--pyharm-python", default=None, help="an interpreter with pyHarm installed")
    ap.add_argument("--pyharm-only", nargs=3, type=int, metavar=("N", "H", "ROUNDS"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.pyharm_only:  # the child process of --pyharm-python: one JSON line
        print(json.dumps(pyharm_curve(*args.pyharm_only)))
        return
    print(f"{'curve':<44} {'points':>6} {'wall s':>9} {'CPU s':>9} {'CPU ms/pt':>9}  folds (rad/s)")
    duff = periodyn_rows("Duffing", duffing(), 7, args.rounds)
    peer = pyharm_rows("Duffing", 1, 7, args.rounds, args.pyharm_python)
    def on_off(t):
        return (f"stability on / off wall {t['stability on'] / t['stability off']:.2f}, "
                f"CPU {t['stability on cpu'] / t['stability off cpu']:.2f}")

    lines = [f"Duffing: {on_off(duff)}"]
    if peer:
        lines.append(f"pyHarm (no stability) / periodyn (stability on) per curve: wall {peer['wall'] / duff['stability on']:.2f}, "
                     f"CPU {peer['cpu'] / duff['stability on cpu']:.2f}")
    for n in (10,) if args.skip_40 else (10, 40):
        t = periodyn_rows(f"chain {n}", chain(n), 10, args.rounds)
        pyharm_rows(f"chain {n}", n, 10, args.rounds if n == 10 else 1, args.pyharm_python)  # pyHarm: 2-3 min a curve
        lines.append(f"chain {n}: {on_off(t)}")
    print("; ".join(lines))


if __name__ == "__main__":
    main()
