"""Stability method "auto": chosen by estimated cost and recorded on the result."""

import numpy as np

import periodyn
from periodyn.speeds import SpeedSolver
from periodyn.examples.chain import parametric_chain
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
from periodyn.harmonic import HarmonicOperator
from periodyn.stability.methods import choose_method, hill_cost, hill_costs_many, operator_exponents
from periodyn.model.linearization import omega_split


def test_auto_takes_sparse_for_a_large_soft_system_and_dense_for_a_stiff_one():
    """The parametric chain (n = 20, m = 20: size 1640, top frequency 200 rad/s, 2 shifts)
    is 8-15x faster by ARPACK; the slider-crank with 8 rod elements (size 800 at m = 12,
    element modes far above m omega / 2: many shifts) is 25x faster dense, where the old
    size rule (> 600: sparse) took sparse."""
    chain = HarmonicOperator.for_model(parametric_chain(20, samples=88), 20).at(2 * np.sqrt(1e4) / 6)
    method, reason = choose_method(chain)
    assert method == "sparse" and "2 shifts" in reason
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=8))
    crank = omega_split(slider_crank_model(0.04 / w1, rod_elements=8), 64)
    op = HarmonicOperator.for_model(crank, 12).at(200.0)
    assert 2 * op.pattern.size == 800 and choose_method(op)[0] == "dense"


def test_costs_over_a_sweep_equal_the_per_operator_costs():
    """The sweep's cost estimates (shift counts from the mean blocks alone) are those of
    the full operator at each speed, on both sides of the dense/sparse choice."""
    chain = HarmonicOperator.for_model(parametric_chain(20, samples=88), 20)
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=8))
    crank = HarmonicOperator.for_model(omega_split(slider_crank_model(0.04 / w1, rod_elements=8), 64), 12)
    for harmonic, speeds in ((chain, [5.0, 33.3, 80.0]), (crank, [150.0, 220.0, 300.0])):
        many = hill_costs_many(harmonic, np.array(speeds))
        assert many == [hill_cost(harmonic.at(w)) for w in speeds]
    assert {c[0] for c in hill_costs_many(chain, np.array([33.3]))} == {"sparse"}


def test_auto_records_its_choice_and_equals_the_chosen_method():
    """On the pendulum auto takes Magnus (certified by step doubling, cheaper than dense
    Hill): the same exponents as the fixed-step Magnus monodromy of the order and steps it
    used, per call and in the speed solver."""
    model = periodyn.examples.pendulum(samples=36)
    w = 0.8 * model.metadata["omega0"]
    auto = periodyn.characteristic_exponents(model.at(w), 8)
    assert auto.method == "magnus" and auto.reason.startswith("Magnus of order 6 with ") and "dense Hill" in auto.reason
    steps = int(auto.reason.split(" with ")[1].split()[0])
    solver = SpeedSolver(model, 8)
    chosen, _ = solver.ladder._moduli(np.array([w]), steps, 6)
    np.testing.assert_allclose(auto.exponents, chosen[0], rtol=1e-12)
    method, reason = solver.stability_methods([w])[0]  # same rule, same steps
    assert method == "magnus" and reason.split(":")[0] == auto.reason.split(":")[0]
    hill = SpeedSolver(model, 8).hill_methods([w])[0]
    assert hill[0] == "dense" and "estimated dense" in hill[1]
    assert operator_exponents(HarmonicOperator.for_system(model.at(w), 8).at(w)).reason == hill[1]
