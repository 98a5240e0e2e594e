"""The continuation corrector that reuses factorizations (palc reuse mode) and its GMRES.

The reuse mode is a chord iteration with exact tangents solved by preconditioned GMRES; it
must trace the branch Newton's corrector traces (same folds and stability changes, every
point converged to tol) with fewer factorizations.
"""

import importlib

import numpy as np
import scipy.linalg as sla

from periodyn.arclength import continuation
from periodyn.examples.dae_examples import duffing
from periodyn.numerics.krylov import gmres

driver = importlib.import_module("periodyn.arclength.driver")
palc = importlib.import_module("periodyn.arclength.palc")


def test_gmres_with_a_nearby_factorization_solves_to_its_tolerance():
    rng = np.random.default_rng(3)
    A = rng.standard_normal((60, 60)) + 8 * np.eye(60)
    lu = sla.lu_factor(A + 0.3 * rng.standard_normal((60, 60)))  # preconditioner of a nearby matrix
    b = rng.standard_normal(60)
    x, rel, steps = gmres(lambda v: A @ v, b, lambda v: sla.lu_solve(lu, v), rtol=1e-12, max_steps=40)
    np.testing.assert_allclose(x, np.linalg.solve(A, b), rtol=0, atol=1e-10 * np.abs(x).max())
    assert rel <= 1e-12 and 1 < steps < 40
    assert abs(np.linalg.norm(b - A @ x) / np.linalg.norm(b) - rel) < 1e-11  # the estimate is the true residual
    x, rel, steps = gmres(lambda v: A @ v, b, lambda v: sla.lu_solve(lu, v), rtol=1e-14, max_steps=2)
    assert steps == 2 and rel > 1e-14  # not reached: reported, not hidden
    assert gmres(lambda v: A @ v, np.zeros(60), lambda v: v, rtol=1e-8, max_steps=5)[2] == 0


def _counted(monkeypatch):
    calls = [0]
    real = palc.lu_factor

    def lu_factor(J):
        calls[0] += 1
        return real(J)
    monkeypatch.setattr(palc, "lu_factor", lu_factor)
    return calls


def test_reuse_corrector_traces_newtons_branch_with_fewer_factorizations(monkeypatch):
    system = duffing(0.05, 1.0, 0.1)
    calls = _counted(monkeypatch)
    newton_branch = continuation(system, (0.6, 1.8), harmonics=7)
    newton_calls = calls[0]
    monkeypatch.setattr(driver, "_REUSE_SIZE", 0)  # the Duffing IHB problem is small: force the reuse mode
    calls[0] = 0
    reuse_branch = continuation(system, (0.6, 1.8), harmonics=7)
    assert reuse_branch.status == "parameter range covered"
    assert np.all(reuse_branch.residual <= 1e-8)
    assert calls[0] < 0.6 * newton_calls
    for kind in ("fold", "neimark-sacker", "period-doubling", "branch-point"):
        a = sorted(p.omega for p in newton_branch.points(kind))
        b = sorted(p.omega for p in reuse_branch.points(kind))
        assert len(a) == len(b)
        np.testing.assert_allclose(b, a, rtol=1e-8)
    folds_a = sorted(newton_branch.points("fold"), key=lambda p: p.omega)
    folds_b = sorted(reuse_branch.points("fold"), key=lambda p: p.omega)
    assert len(folds_a) == 2
    for pa, pb in zip(folds_a, folds_b):
        np.testing.assert_allclose(pb.amplitude, pa.amplitude, rtol=1e-7)
