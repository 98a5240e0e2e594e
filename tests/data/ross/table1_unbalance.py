"""Regenerate table1_unbalance.json: the unbalance response of the rotor of Table I
(Schwab & Meijaard 2001, section 4.3) computed by ROSS's ``run_unbalance_response``.

ROSS is not a dependency of periodyn; run this script in an environment that has it:

    python3 -m venv /tmp/rossenv && /tmp/rossenv/bin/pip install ross-rotordynamics
    /tmp/rossenv/bin/python tests/data/ross/table1_unbalance.py

The rotor is built here from the paper's data in SI (the conversion factors of
periodyn.examples.rotor_table1), as ROSS models it: five Euler-Bernoulli shaft elements
(shear_effects=False, rotary inertia and gyroscopic terms on), bearings, the seal as a
cross-coupled bearing element, the seal's added mass as a disk without inertia (ROSS's
PointMass lives on a node of its own), two disks. ROSS's
axis is z and its lateral coordinates x, y, alpha, beta are periodyn's y, z, ry, rz.
"""

import json
from pathlib import Path

import numpy as np
import ross as rs

INCH, POUND, POUND_FORCE = 0.0254, 0.45359237, 4.4482216
STIFFNESS = DAMPING = POUND_FORCE / INCH
SPEEDS_RPM = [1000.0, 2130.0, 4000.0, 10000.0, 18700.0]
UNBALANCE = {"node": [4, 5], "magnitude": [1.0e-4, 5.0e-5], "phase": [0.0, np.pi / 3]}   # kg m, rad


def table1_rotor():
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


def main():
    rotor = table1_rotor()
    speeds = np.array(SPEEDS_RPM) * np.pi / 30.0
    result = rotor.run_unbalance_response(UNBALANCE["node"], UNBALANCE["magnitude"], UNBALANCE["phase"],
                                          frequency=speeds)
    X = np.asarray(result.forced_resp)                     # (ndof, speeds), x = Re(X exp(i w t))
    per_node = rotor.number_dof
    lateral = [per_node * node + np.array([0, 1, 3, 4] if per_node == 6 else [0, 1, 2, 3])
               for node in range(len(rotor.nodes))]
    X = X[np.concatenate(lateral)].T                        # (speeds, 4 nodes): x, y, alpha, beta
    data = {"description": __doc__.split("\n\n")[0].replace("\n", " "),
            "ross_version": rs.__version__, "speeds_rpm": SPEEDS_RPM, "unbalance": UNBALANCE,
            "coordinates": "per node x, y, alpha, beta (periodyn y, z, ry, rz); m, rad",
            "response_real": X.real.tolist(), "response_imag": X.imag.tolist()}
    out = Path(__file__).with_suffix(".json")
    out.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {out}: {X.shape[0]} speeds x {X.shape[1]} coordinates, ROSS {rs.__version__}")


if __name__ == "__main__":
    main()
