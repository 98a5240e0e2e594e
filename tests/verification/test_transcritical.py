"""A transcritical branch point of periodic orbits and switching onto the crossing branch.

    x'' + c x' + (mu + beta y^2) x + x^2 = 0,    y'' + c y' + y = f cos(w t)

(c = 0.1, beta = 0.6, f = 3, w = 2; parameter mu). The orbit x = 0, y = the linear response is
a branch for every mu; its x-mode obeys the Hill equation x'' + c x' + (mu + beta y(t)^2) x = 0,
whose real multiplier crosses +1 at one mu* (near -beta <y^2> = -0.3; the parametric resonances
need mu near (k w)^2 >= 4). There the branch x ~ -(mu - mu*) (to first order) crosses it without
a fold and the two exchange stability: a transcritical point, not a pitchfork (no symmetry
x -> -x because of the x^2 term), so the two halves of the crossing branch differ.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from periodyn import DAE
from periodyn.arclength import continuation, switch_branch
from periodyn.errors import InputError

C, BETA, F, W = 0.1, 0.6, 3.0, 2.0


def _system():
    def force(q, qd, t, w, P):
        x, y = q[0], q[1]
        return np.array([-C * qd[0] - (P["mu"] + BETA * y ** 2) * x - x ** 2, -C * qd[1] - y + F * np.cos(w * t)])
    return DAE(np.eye(2), force, parameters={"mu": 1.0}, coordinate_names=("x", "y"), name="transcritical")


@pytest.fixture(scope="module")
def trivial():
    return continuation(_system(), W, 5, parameter=("mu", 1.0, -1.0))


def _hill_multipliers(mu):
    """Multipliers of x'' + c x' + (mu + beta y(t)^2) x = 0 with the exact linear response y
    (DOP853 over one period, independent of periodyn)."""
    Y = F / (1 - W ** 2 + 1j * C * W)

    def rhs(t, z):
        y = (Y * np.exp(1j * W * t)).real
        return [z[1], -C * z[1] - (mu + BETA * y * y) * z[0]]
    T = 2 * np.pi / W
    cols = [solve_ivp(rhs, (0, T), e, method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1] for e in np.eye(2)]
    return np.linalg.eigvals(np.array(cols).T)


def test_transcritical_point_is_detected_typed_and_confirmed_by_the_monodromy(trivial):
    assert all(abs(s.mean[0]) < 1e-12 and np.abs(s.harmonics[:, 0]).max() < 1e-12 for s in trivial.solutions)
    (bp,) = trivial.special_points
    assert bp.type == "branch-point" and -0.35 < bp.parameter < -0.25
    assert abs(bp.multiplier - 1) < 1e-9
    k = bp.index
    assert trivial.stable[k] and not trivial.stable[k + 1]  # stable above mu*, unstable below
    # the integrated Hill equation has its multiplier +1 there (measured 1e-7 off: Magnus path)
    assert np.min(np.abs(_hill_multipliers(bp.parameter) - 1)) < 1e-5
    # and on either side of mu* it is clearly inside / outside the unit circle
    assert np.max(np.abs(_hill_multipliers(bp.parameter + 0.05))) < 1 < np.max(np.abs(_hill_multipliers(bp.parameter - 0.05)))
    # the critical vector is the constant x-mode: its largest unknown is a_0 of x
    assert int(np.argmax(np.abs(bp.eigenvector))) == 0


def test_switching_reaches_both_halves_of_the_crossing_branch(trivial):
    (bp,) = trivial.special_points
    below = switch_branch(trivial, bp, -0.6, side=1)
    above = switch_branch(trivial, bp, 0.0, side=-1)
    for br, stop in ((below, -0.6), (above, 0.0)):
        assert br.status == "parameter range covered" and abs(br.parameter[-1] - stop) < 0.1
        assert br.points("branch-point") == []  # the start (the crossing itself) is not reported again
    xb = np.array([s.mean[0] for s in below.solutions])
    xa = np.array([s.mean[0] for s in above.solutions])
    # below mu*: x > 0 and stable; above: x < 0 and unstable (exchange of stability with x = 0);
    # the first step is along the critical vector at fixed mu, so mu moves from the second on
    assert np.all(xb[1:] > 0) and np.all(below.stable[1:]) and np.all(below.parameter[2:] < bp.parameter)
    assert np.all(xa[1:] < 0) and not np.any(above.stable[1:]) and np.all(above.parameter[2:] > bp.parameter)
    # transcritical: x ~ -(mu - mu*) on both sides (slope -1 of the averaged equation, to 15 %)
    for br, x in ((below, xb), (above, xa)):
        j = int(np.argmin(np.abs(np.abs(br.parameter - bp.parameter) - 0.1)))
        assert abs(x[j] / (br.parameter[j] - bp.parameter) + 1) < 0.15
    with pytest.raises(InputError, match="side"):
        switch_branch(trivial, bp, 0.0, side=2)
