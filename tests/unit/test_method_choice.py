"""Stability method "auto": chosen by estimated cost and recorded on the result."""

import numpy as np

import periodyn
from periodyn.analysis import SpeedSolver
from periodyn.examples.chain import parametric_chain
from periodyn.examples.slider_crank import first_bending_frequency, slider_crank_model
from periodyn.harmonic import HarmonicOperator
from periodyn.hill import choose_method
from periodyn.linearize import omega_split


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


def test_auto_records_its_choice_and_equals_the_chosen_method():
    model = periodyn.examples.pendulum(samples=36)
    w = 0.8 * model.metadata["omega0"]
    auto = periodyn.characteristic_exponents(model.at(w), 8)
    chosen = periodyn.characteristic_exponents(model.at(w), 8, auto.method)
    assert auto.method == "dense" and "estimated dense" in auto.reason and chosen.reason == ""
    np.testing.assert_array_equal(auto.exponents, chosen.exponents)
    assert SpeedSolver(model, 8).hill_methods([w])[0] == (auto.method, auto.reason)
