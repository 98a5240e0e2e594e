"""The lean flow of ODEs with a constant mass (``periodyn.kernels.solvers.ode_flow`` behind
``periodyn.numerics.variational.flow``) against the NumPy path (the same ODE given with a
callable mass, solved per stage), and its omega sensitivity against central differences
of the end state in omega."""

import numpy as np
import pytest

from periodyn import DAE
from periodyn.errors import InputError
from periodyn.numerics.variational import flow

MASS = np.array([[2.0, 0.3], [0.3, 1.0]])


def coupled(mass, phase_forcing=True, unbalance=False):
    """Two coupled Duffing oscillators under F cos(omega t) (or an unbalance F omega^2 cos(omega t))."""

    def force(q, qd, t, w, P):
        drive = P["F"] * (w * w if unbalance else 1.0) * np.cos(w * t)
        return np.array([-0.1 * qd[0] - 1.0 * q[0] - 0.5 * q[0] ** 3 + 0.4 * (q[1] - q[0]) + drive,
                         -0.05 * qd[1] - 2.0 * q[1] + 0.4 * (q[0] - q[1]) - 0.2 * q[1] * qd[1] ** 2])

    def jac(q, qd, t, w, P):
        return (np.array([[-1.4 - 1.5 * q[0] ** 2, 0.4], [0.4, -2.4 - 0.2 * qd[1] ** 2]]),
                np.array([[-0.1, 0.0], [0.0, -0.05 - 0.4 * q[1] * qd[1]]]))

    return DAE(mass, force, force_jacobian=jac, parameters={"F": 0.5}, n=2, name="coupled", phase_forcing=phase_forcing)


@pytest.mark.parametrize("parameter, unbalance", [(None, False), (None, True), ("F", False)])
def test_lean_flow_matches_the_numpy_flow(parameter, unbalance):
    lean = coupled(MASS, phase_forcing=not unbalance, unbalance=unbalance)
    plain = coupled(lambda q: MASS, phase_forcing=False, unbalance=unbalance)
    assert plain.mass_jacobian is not None  # a callable mass: the general per-stage path
    rng = np.random.default_rng(5)
    y0 = 0.3 * rng.standard_normal((2, 4))
    kw = dict(directions=rng.standard_normal((2, 4, 3)), sensitivity=rng.standard_normal((2, 4)),
              parameter=parameter, rtol=1e-11, atol=1e-12)
    fast = flow(lean, 1.3, y0, np.array([0.0, 0.7]), 2.0, **kw)
    ref = flow(plain, 1.3, y0, np.array([0.0, 0.7]), 2.0, **kw)
    assert np.max(np.abs(fast.y - ref.y)) < 1e-12
    assert np.max(np.abs(fast.columns - ref.columns)) < 1e-11 * max(1.0, np.max(np.abs(ref.columns)))
    # the NumPy path takes a forward difference of G in p (relative step 1e-5, so an error of
    # about 1e-5 relative); the lean one is exact in the scaling part (checked in the next test)
    assert np.max(np.abs(fast.sensitivity - ref.sensitivity)) < 3e-5 * max(1.0, np.max(np.abs(ref.sensitivity)))


@pytest.mark.parametrize("phase_forcing, unbalance", [(True, False), (False, False), (False, True)])
def test_omega_sensitivity_matches_central_differences(phase_forcing, unbalance):
    system = coupled(MASS, phase_forcing=phase_forcing, unbalance=unbalance)
    y0, omega, h = np.array([[0.3, -0.2, 0.1, 0.4]]), 1.1, 1e-4
    f = flow(system, omega, y0, 0.0, 2 * np.pi, sensitivity=np.zeros((1, 4)), rtol=1e-12, atol=1e-13)
    end = [flow(system, omega + s * h, y0, 0.0, 2 * np.pi, rtol=1e-13, atol=1e-14).y for s in (1.0, -1.0)]
    fd = (end[0] - end[1]) / (2 * h)  # truncation ~h^2 |y'''| ~ 1e-8
    # exact scaling part; an explicit omega-dependence (unbalance) is a forward difference (step 1e-5 relative)
    tol = 1e-5 if unbalance else 1e-6
    assert np.max(np.abs(f.sensitivity - fd)) < tol * max(1.0, np.max(np.abs(fd)))


def test_a_false_phase_forcing_declaration_is_refused():
    system = coupled(MASS, phase_forcing=True, unbalance=True)  # F omega^2 cos(omega t) moves with omega
    with pytest.raises(InputError, match="phase_forcing"):
        flow(system, 1.1, np.array([[0.3, -0.2, 0.1, 0.4]]), 0.0, 1.0, sensitivity=np.zeros((1, 4)))
