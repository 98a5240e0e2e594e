"""Shared fixtures: small systems with known answers.

The suite runs one BLAS/OpenMP thread per process, as sweep workers do (and the
subprocesses it starts inherit that): on the small matrices of these tests extra BLAS
threads only wait for each other, and on a loaded 2-core machine the OpenBLAS of older
wheels (numpy 1.26, scipy 1.11) made a Numba kernel calling LAPACK 40 times slower."""

import atexit
import os
import shutil
import tempfile

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "VECLIB_MAXIMUM_THREADS"):
    os.environ.setdefault(_var, "1")
# models built from sweep files are cached for this session only (and its subprocesses), not in the user's cache
os.environ["PERIODYN_CACHE_DIR"] = tempfile.mkdtemp(prefix="periodyn-tests-cache-")
atexit.register(shutil.rmtree, os.environ["PERIODYN_CACHE_DIR"], True)
# a user's warm server (periodyn serve) never runs the suite's commands; tests/integration/test_server.py starts its own
os.environ["PERIODYN_SERVER"] = "off"

import numpy as np  # noqa: E402
import pytest  # noqa: E402
import scipy.linalg  # noqa: E402,F401  (its BLAS loaded before the limit below)
from threadpoolctl import threadpool_limits  # noqa: E402

threadpool_limits(1)  # also where numpy or scipy was imported before this file

import periodyn  # noqa: E402


def mathieu(a: float, q: float, samples: int = 32, zeta: float = 0.0) -> periodyn.RheoLinear:
    """x'' + 2 zeta x' + (a - 2q cos 2t) x = 0: period pi, omega = 2."""
    return periodyn.RheoLinear.from_functions(
        lambda t: 1.0, lambda t: 2 * zeta, lambda t: a - 2 * q * np.cos(2 * t), lambda t: 0.0, 2.0, samples)


def two_dof_parametric(omega: float, eps: float = 0.3, samples: int = 32) -> periodyn.RheoLinear:
    """2-DOF system with time-varying mass and stiffness coupling and forcing:
    M(t) = I + 0.2 sin(wt) E, K(t) = diag(w1^2, w2^2) + eps cos(wt) S (S symmetric
    coupling), light damping; w1 = 1, w2 = 2.3 rad/s."""
    E = np.array([[1.0, 0.3], [0.3, 0.5]])
    S = np.array([[0.5, 1.0], [1.0, -0.4]])
    K0 = np.diag([1.0, 2.3**2])
    C = np.array([[0.02, 0.0], [0.0, 0.03]])
    return periodyn.RheoLinear.from_functions(
        lambda t: np.eye(2) + 0.2 * np.sin(omega * t) * E,
        lambda t: C,
        lambda t: K0 + eps * np.cos(omega * t) * S,
        lambda t: np.array([np.cos(omega * t), 0.3 * np.sin(2 * omega * t)]),
        omega, samples, coordinate_names=("x1", "x2"))


def assert_same_spectrum(a, b, atol):
    """Two sets of complex numbers equal up to order (optimal one-to-one matching)."""
    from scipy.optimize import linear_sum_assignment

    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    cost = np.abs(a[:, None] - b[None, :])
    i, j = linear_sum_assignment(cost)
    worst = cost[i, j].max()
    assert worst <= atol, f"spectra differ by {worst:.3g} > {atol:.3g}:\n{np.sort_complex(a)}\n{np.sort_complex(b)}"


@pytest.fixture
def pendulum_model():
    return periodyn.examples.pendulum(samples=32)
