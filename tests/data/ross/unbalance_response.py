"""Regenerate unbalance_response.json: unbalance responses computed by ROSS's
``run_unbalance_response`` for two rotors that periodyn builds the same way.

ROSS is not a dependency of periodyn; run this script in an environment that has it:

    python3 -m venv /tmp/rossenv && /tmp/rossenv/bin/pip install ross-rotordynamics "plotly<6"
    /tmp/rossenv/bin/python tests/data/ross/unbalance_response.py

(ROSS 2.3 fails to import with plotly 6 or newer.) Both rotors are built here from their
data in SI: Euler-Bernoulli shaft elements (shear_effects=False, rotary inertia and
gyroscopic terms on), linear bearings, disks; a lumped lateral mass is a disk without
inertia (ROSS's PointMass lives on a node of its own). ROSS's axis is z and its lateral
coordinates x, y, alpha, beta are periodyn's y, z, ry, rz.

* ``table1``: the rotor of Table I (Schwab & Meijaard 2001, section 4.3; the conversion
  factors of periodyn.examples.rotor_table1), the seal as a cross-coupled bearing;
* ``anisotropic``: a shaft 0.6 m long in 3 elements on two anisotropic, cross-coupled
  bearings with an overhung disk (elliptic orbits, forward and backward whirl), with
  ROSS's major axis of every node's orbit.
"""

import json
from pathlib import Path

import numpy as np
import ross as rs

INCH, POUND, POUND_FORCE = 0.0254, 0.45359237, 4.4482216
STIFFNESS = DAMPING = POUND_FORCE / INCH


def table1():
    steel = rs.Material(name="table1_steel", rho=0.283 * POUND / INCH**3, E=3.0e7 * POUND_FORCE / INCH**2,
                        Poisson=0.3)
    shaft = [rs.ShaftElement(L=10 * INCH, idl=0.0, odl=4 * INCH, material=steel, shear_effects=False,
                             rotary_inertia=True, gyroscopic=True) for _ in range(5)]
    k = 1.0e5 * STIFFNESS
    bearings = [rs.BearingElement(n=n, kxx=k, kyy=k, cxx=0.0, cyy=0.0) for n in (0, 1)]
    K, kc, C, c = 89_542 * STIFFNESS, 27_028 * STIFFNESS, 171.42 * DAMPING, 12.0 * DAMPING
    bearings.append(rs.BearingElement(n=2, kxx=K, kyy=K, kxy=kc, kyx=-kc, cxx=C, cyy=C, cxy=c, cyx=-c))
    disk_mass, inertia = 0.028 * POUND_FORCE / INCH, POUND_FORCE * INCH
    disks = [rs.DiskElement(n=n, m=disk_mass, Id=0.114 * inertia, Ip=0.224 * inertia) for n in (4, 5)]
    disks.append(rs.DiskElement(n=2, m=6.68, Id=0.0, Ip=0.0))   # the seal's added mass on the shaft node
    return rs.Rotor(shaft, disks, bearings)


def anisotropic():
    steel = rs.Material(name="anisotropic_steel", rho=7800.0, E=2.1e11, Poisson=0.3)
    shaft = [rs.ShaftElement(L=0.2, idl=0.0, odl=0.04, material=steel, shear_effects=False, rotary_inertia=True,
                             gyroscopic=True) for _ in range(3)]
    bearings = [rs.BearingElement(n=0, kxx=4e6, kyy=1.5e6, kxy=2e5, cxx=300.0, cyy=150.0),
                rs.BearingElement(n=2, kxx=3e6, kyy=1e6, cxx=200.0, cyy=400.0, cyx=50.0)]
    return rs.Rotor(shaft, [rs.DiskElement(n=3, m=5.0, Id=0.012, Ip=0.02)], bearings)


CASES = {
    "table1": (table1, [1000.0, 2130.0, 4000.0, 10000.0, 18700.0],
               {"node": [4, 5], "magnitude": [1.0e-4, 5.0e-5], "phase": [0.0, np.pi / 3]}),
    "anisotropic": (anisotropic, [1000.0, 4000.0, 8000.0, 15000.0],
                    {"node": [3, 1], "magnitude": [2.0e-5, 1.0e-5], "phase": [0.0, 2.0]}),
}


def case(build, rpm, unbalance):
    rotor = build()
    result = rotor.run_unbalance_response(unbalance["node"], unbalance["magnitude"], unbalance["phase"],
                                          frequency=np.array(rpm) * np.pi / 30.0)
    per_node = rotor.number_dof
    lateral = np.concatenate([per_node * node + np.array([0, 1, 3, 4] if per_node == 6 else [0, 1, 2, 3])
                              for node in range(len(rotor.nodes))])
    X = np.asarray(result.forced_resp)[lateral].T           # (speeds, 4 per node), x = Re(X exp(i w t))
    major = [np.real(result._calculate_major_axis_per_node(node, "major")[3]).tolist() for node in rotor.nodes]
    return {"speeds_rpm": rpm, "unbalance": unbalance, "response_real": X.real.tolist(),
            "response_imag": X.imag.tolist(), "major_axis": np.array(major).T.tolist()}


def main():
    data = {"description": __doc__.split("\n\n")[0].replace("\n", " "), "ross_version": rs.__version__,
            "coordinates": "per node x, y, alpha, beta (periodyn y, z, ry, rz); m, rad; major_axis (speeds, nodes) m",
            "cases": {name: case(*spec) for name, spec in CASES.items()}}
    out = Path(__file__).with_suffix(".json")
    out.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {out}: cases {list(CASES)}, ROSS {rs.__version__}")


if __name__ == "__main__":
    main()
