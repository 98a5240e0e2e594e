"""The jitted variational right-hand side of planar rigid-body DAEs
(``periodyn.kernels.solvers.rigid2d_flow``) against the NumPy path of
``periodyn.numerics.variational`` (the same DAE with its packed arrays hidden): end
states, variational columns and parameter sensitivity of one integration."""

import numpy as np
import pytest

from periodyn.examples.dae_examples import inverted_pendulum, rod_pendulum, slider_rod_pendulum
from periodyn.numerics.variational import flow


@pytest.mark.parametrize("build, parameter", [(lambda: rod_pendulum(1.0, 1.0, 0.1, 1.0), "f"),
                                              (slider_rod_pendulum, None), (inverted_pendulum, "p")])
def test_jitted_flow_matches_the_numpy_flow(build, parameter):
    system = build()
    n, rng = system.n, np.random.default_rng(3)
    y0 = np.concatenate([system.q0 + 0.01 * rng.standard_normal(n), 0.1 * rng.standard_normal(n)])
    y0 = np.array([y0, y0])  # two members, started at different phases
    E = rng.standard_normal((2, 2 * n, 3))
    sens = rng.standard_normal((2, 2 * n))
    kw = dict(directions=E, sensitivity=sens, parameter=parameter, rtol=1e-11, atol=1e-12)
    fast = flow(system, 1.7, y0, np.array([0.0, 0.3]), 1.0, **kw)
    plain = build()
    del plain.planar_arrays
    ref = flow(plain, 1.7, y0, np.array([0.0, 0.3]), 1.0, **kw)
    assert fast.nfev == ref.nfev  # the same steps: the same right-hand side to round-off
    assert np.max(np.abs(fast.y - ref.y)) < 1e-13
    assert np.max(np.abs(fast.columns - ref.columns)) < 1e-11 * max(1.0, np.max(np.abs(ref.columns)))
    # the sensitivity column differences G in p with a 1e-5 step: round-off of the difference
    assert np.max(np.abs(fast.sensitivity - ref.sensitivity)) < 1e-8 * max(1.0, np.max(np.abs(ref.sensitivity)))
