"""The Cardan drive shaft's full non-linear equations (4) against its linearization,
Schwab & Meijaard (2001) section 4.4: "All results presented here show hardly any
difference with full non-linear results." Periodic orbits by shooting on the implicit
one-period map started from the linearized harmonic-balance orbit; the maxima of
Fig. 9-10 along the orbit (through the non-linear kinematics) and the stability verdict
of the shooting monodromy against the linearized ones (Hill).

Measured at the twelve speeds of ``sweeps/cardan_shaft_nonlinear.toml`` (0.30-0.96
omega_b): every verdict agrees (unstable at 0.665, 0.80, 0.85, 0.90; max |mu| 1.12, 1.33,
1.54, 1.28), each orbit in 4 Newton steps from the linearized one; max twist within 0.5 %
of the linearized one everywhere, max midpoint deflection within 0.4 % except near its deep
minimum around 0.75 omega_b, where it is 40 times smaller than at 0.45 (0.9 % at 0.72,
3.4 % at 0.80, 1.4 % at 0.85): "hardly any difference", as the paper says. The map's last
step ends at an input angle of 2 pi, one turn of the input hinge: the constraints take the
hinge angle on the branch nearest its prescribed value (test_prescribed_hinge_turns)."""

import numpy as np
import pytest

import periodyn
from periodyn.examples.cardan import cardan_shaft, cardan_shaft_nonlinear, orbit_maxima


@pytest.fixture(scope="module")
def shaft():
    return cardan_shaft(), cardan_shaft_nonlinear()


def _linear_maxima(system, solution, samples=720):
    t = np.arange(samples) * solution.period / samples
    y = solution.outputs(t)
    names = list(system.output_names)
    return {"deflection": np.abs(y[:, names.index("midpoint_deflection")]).max(),
            "twist": y[:, names.index("twist")].max()}


def _compare(shaft, ratio):
    linear, nonlinear = shaft
    w = ratio * linear.metadata["omega_b"]
    system = linear.at(w)
    hb = periodyn.periodic_solution(system, 12)
    orbit = periodyn.shooting(nonlinear, w, initial=hb, integrator="implicit")
    assert orbit.residual < 1e-9 and orbit.iterations <= 8
    assert orbit.discretization_error < 1e-3
    lin_max = _linear_maxima(system, hb)
    nl_max = orbit_maxima(nonlinear.equations.model, orbit)
    verdict = periodyn.characteristic_exponents(system, 12, method="dense").stable
    return lin_max, nl_max, verdict, orbit


def test_same_model_as_the_linearized_shaft(shaft):
    """Same damping constants and reference frequencies; the ten deformation modes of the
    two beams as coordinates, in the linearized system's order."""
    linear, nonlinear = shaft
    assert nonlinear.metadata == linear.metadata
    assert nonlinear.coordinate_names == tuple(linear.at(300.0).coordinate_names)
    assert nonlinear.n == 10 and nonlinear.m == 0


def test_maxima_and_verdict_agree_away_from_resonance(shaft):
    """0.45 omega_b (between the resonances near omega_b/3 and omega_b/2, stable): max
    midpoint deflection and max twist within 3 % of the linearized ones, both stable."""
    lin_max, nl_max, verdict, orbit = _compare(shaft, 0.45)
    assert nl_max["deflection"] == pytest.approx(lin_max["deflection"], rel=0.03)
    assert nl_max["twist"] == pytest.approx(lin_max["twist"], rel=0.03)
    assert verdict is True and orbit.stable is True


@pytest.mark.slow
@pytest.mark.parametrize("ratio, stable", [(0.62, True), (0.665, False), (0.85, False), (0.96, True)])
def test_verdicts_inside_and_beside_the_unstable_zones(shaft, ratio, stable):
    """The zones 0.65-0.68 and 0.78-0.92 of omega_b: the non-linear orbit exists there
    (shooting converges from the linearized orbit) and its multipliers give the linearized
    verdict; its maxima stay within 5 % of the linearized ones."""
    lin_max, nl_max, verdict, orbit = _compare(shaft, ratio)
    assert verdict is stable and orbit.stable is stable
    for key in ("deflection", "twist"):
        assert nl_max[key] == pytest.approx(lin_max[key], rel=0.05), key
