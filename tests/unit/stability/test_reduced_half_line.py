"""Exponents on the line Im(lambda) = w/2 (negative real multipliers): the reduced-Hill null
vector's harmonic centroid is +-1/2, and the shift by one harmonic only swaps the two equally
centred vectors. Such speeds were handed to the full model (16 s per speed at 32 rod
elements); they are certified now, within their bound of the fine full-model reference."""

import numpy as np

from periodyn.stability.reduced import ReducedStability

from .test_reduced import crank, reference


def test_top_exponents_on_the_half_line_are_certified_within_the_bound():
    model = crank(8)
    w = np.array([231.54, 231.6])
    exps, done, reasons, records = ReducedStability(model).solve(w, 12)
    top = exps[np.arange(w.size), np.argmax(exps.real, axis=1)]
    assert np.allclose(top.imag % w, w / 2, rtol=1e-12)  # the case in question
    assert done.all(), reasons
    err = np.abs(exps.real.max(axis=1) * 2 * np.pi / w - reference(model, w))
    assert np.all(err <= records["stability_error_bound"]) and np.all(err <= 1e-8)
