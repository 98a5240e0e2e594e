"""Rotors built as element models and rotors without damping: bad input is refused with
the fix named (a joint axis of zero length, a bearing off the stations, a singular mass
matrix, an anisotropic support for the co-rotating adapter), and an undamped rotor
crossing its critical speeds is neither unstable from rounding nor lost by the subset
solver where its frequencies are double."""

import numpy as np
import pytest

from periodyn.errors import InputError
from periodyn.model import Model
from periodyn.model.elements import IndependentElement
from periodyn.rotor import Bearing, ElementRotor, Rotor, campbell, spatial_rotor, spatial_rotor_model

E, RHO, D, LEN = 2.1e11, 7800.0, 0.05, 0.6


def _undamped(elements=3, bearings=True, density=RHO):
    r = Rotor("undamped")
    r.add_shaft(0.0, LEN, outer_diameter=D, E=E, density=density, elements=elements)
    if bearings:
        for at in (0.0, LEN):
            r.add_bearing(Bearing(at, kyy=5e6, kzz=5e6))
    r.add_disk(LEN / 3, 6.0, 0.03, 0.016)
    return r


def test_undamped_rotor_across_its_critical_speeds_is_neutral():
    """No damping: every eigenvalue is on the imaginary axis (to rounding, ~1e-10 1/s),
    so no threshold speed although the speed range crosses forward critical speeds (a
    forward whirl frequency equal to the spin); both frames agree, whirls included."""
    model = _undamped().compile()
    speeds = np.linspace(0.0, 1500.0, 301)
    a, b = campbell(model, speeds, modes=6, frame="rotating"), campbell(model, speeds, modes=6, frame="stationary")
    forward = b.whirl.values == "forward"
    crossing = np.diff(np.sign(b.frequency.values - speeds[:, None]), axis=0) != 0
    assert (crossing & forward[1:]).any()                 # a forward critical speed lies in the range
    assert np.abs(b.max_real_eigenvalue.values).max() < 1e-6
    assert np.isnan(a.attrs["threshold_speed"]) and np.isnan(b.attrs["threshold_speed"])
    np.testing.assert_allclose(a.eigenvalue.values, b.eigenvalue.values, rtol=1e-9, atol=1e-6)
    assert (a.whirl.values[1:] == b.whirl.values[1:]).all()   # at rest forward and backward coincide


def test_subset_solver_at_rest_of_an_undamped_rotor_matches_the_dense_one(monkeypatch):
    """At rest an undamped isotropic rotor has every frequency twice; the subset solver
    gives the eigenvalues nearest the origin there as the dense one does, whether ARPACK
    converges (it does with some scipy releases) or its non-convergence sends the speed to
    the dense solver; that fallback is forced below so it is checked with every release."""
    import scipy.sparse.linalg
    from scipy.sparse.linalg import ArpackNoConvergence

    model = _undamped(elements=9).compile()
    speeds = [0.0, 200.0]
    dense = campbell(model, speeds, modes=4, eigensolver="dense", frame="stationary")
    subset = campbell(model, speeds, modes=4, eigensolver="subset")
    np.testing.assert_allclose(subset.eigenvalue.values, dense.eigenvalue.values, rtol=1e-8, atol=1e-6)
    assert (subset.whirl.values[1] == dense.whirl.values[1]).all()

    def no_convergence(*args, **kwargs):
        raise ArpackNoConvergence("forced", np.empty(0), np.empty((0, 0)))

    monkeypatch.setattr(scipy.sparse.linalg, "eigs", no_convergence)
    fallen = campbell(model, speeds, modes=4, eigensolver="subset")
    assert fallen.attrs["dense_fallback_speeds"] == 2
    np.testing.assert_allclose(fallen.eigenvalue.values, dense.eigenvalue.values, rtol=1e-8, atol=1e-6)
    monkeypatch.undo()
    free = _undamped(elements=9, bearings=False).compile()
    with pytest.raises(InputError, match="non-singular stiffness.*unsupported rotor.*add bearings or use eigensolver='dense'"):
        campbell(free, [10.0], modes=2, eigensolver="subset")


def test_spatial_rotor_refuses_bad_input_with_the_fix():
    r = _undamped()
    r.add_bearing(Bearing(0.25, kyy=1e6, kzz=1e6))     # stations at 0, 0.2, 0.4, 0.6 m
    with pytest.raises(InputError, match=r"bearing at 0.25 m is not on a station; stations are at \[0.0, 0.2"):
        spatial_rotor_model(r)
    with pytest.raises(InputError, match="singular mass matrix"):
        spatial_rotor_model(_undamped(density=0.0))       # the shaft's modes carry no mass
    with pytest.raises(InputError, match="spatial_rotor_model takes a Rotor"):
        spatial_rotor_model(_undamped().compile())
    with pytest.raises(InputError, match="carrier_length must be a positive length"):
        spatial_rotor_model(_undamped(), carrier_length=0.0)
    aniso = _undamped()
    aniso.add_bearing(Bearing(0.2, kyy=2e6, kzz=5e5))
    with pytest.raises(InputError, match="depend on the spin angle.*omega_split"):
        spatial_rotor(aniso)
    element = spatial_rotor(_undamped())
    with pytest.raises(InputError, match="only frame='rotating' exists"):
        campbell(element, [10.0], frame="stationary")
    with pytest.raises(InputError, match="use eigensolver='dense'"):
        campbell(element, [10.0], eigensolver="subset")


def test_element_model_rotor_inputs_are_checked():
    model = spatial_rotor_model(_undamped())
    with pytest.raises(InputError, match=r"stations \['Q1'\] are not points of the model"):
        ElementRotor.from_model(model, ["P0", "Q1"])
    m = Model("no_spin", dimension=3)
    m.add_orientation("ground")
    m.fix("ground")
    m.add_orientation("shaft")
    with pytest.raises(InputError, match="axis must be a finite non-zero 3-vector"):
        m.add_hinge("motor", ("ground", "shaft"), axis=(0.0, 0.0, 0.0))
    with pytest.raises(InputError, match="axis must be a finite non-zero 3-vector"):
        m.add_universal_joint("u", ("ground", "shaft"), axes=[(0.0, 0.0, 0.0), (0.0, 0.0, 1.0)])
    m.add_point("P", (0.0, 0.0, 0.0))
    with pytest.raises(InputError, match="unknown nodal coordinate 'Q.y'"):   # a bearing on a missing node
        m.add_independent(IndependentElement("bearing", ("Q.y", "Q.z"), stiffness=(np.eye(2),)))
    m.fix("P")
    m.fix("shaft")
    with pytest.raises(InputError, match="needs exactly one, the spin angle"):
        ElementRotor.from_model(m.compile(), ["P"])
