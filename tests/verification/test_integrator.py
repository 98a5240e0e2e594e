"""The one integrator wrapper (periodyn.numerics.integration.solve) against analytic solutions."""

import numpy as np
import pytest

from periodyn.errors import InputError
from periodyn.numerics.integration import solve


def stiff_linear():
    """y' = A y + b cos t with eigenvalues -1, -1e4 (stiffness ratio 1e4) and its exact solution."""
    V = np.array([[1.0, 1.0], [1.0, -1.0]]) / np.sqrt(2)
    lam = np.array([-1.0, -1e4])
    A = V @ np.diag(lam) @ V.T
    b = np.array([1.0, 0.5])
    y0 = np.array([1.0, -2.0])
    # particular solution y_p = Re(c e^{it}), (i I - A) c = b
    c = np.linalg.solve(1j * np.eye(2) - A, b)

    def exact(t):
        yp0 = c.real
        # e^{A t} = V e^{lam t} V^T exactly (V orthogonal); scipy 1.11's expm overflows its
        # 2x2 formula (cosh of 5e3 t) for this A
        return np.array([V @ (np.exp(lam * ti) * (V.T @ (y0 - yp0))) + (c * np.exp(1j * ti)).real
                         for ti in np.atleast_1d(t)])

    return A, b, y0, exact


def test_radau_with_analytic_jacobian_matches_exact_and_dop853():
    A, b, y0, exact = stiff_linear()
    rhs = lambda t, y: A @ y + b * np.cos(t)  # noqa: E731
    t = np.linspace(0.0, 3.0, 7)
    radau = solve(rhs, (0.0, 3.0), y0, t_eval=t, method="Radau", jac=lambda t, y: A, rtol=1e-10, atol=1e-12)
    dop = solve(rhs, (0.0, 3.0), y0, t_eval=t, rtol=1e-10, atol=1e-12)
    ref = exact(t)
    assert np.max(np.abs(radau.y.T - ref)) < 1e-8
    assert np.max(np.abs(dop.y.T - ref)) < 1e-8
    # the implicit method with the analytic Jacobian needs far fewer right-hand sides than the explicit one
    assert radau.nfev < dop.nfev / 5


def test_jacobian_refused_for_explicit_method():
    with pytest.raises(InputError, match="implicit"):
        solve(lambda t, y: -y, (0.0, 1.0), np.ones(1), jac=lambda t, y: -np.eye(1))
