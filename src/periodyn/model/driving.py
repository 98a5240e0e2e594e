"""Functions of the driving angle theta = omega t for prescribed motions and loads of an
element model (Schwab & Meijaard 2001, eq. 2 and 7: any periodic ``q^r(t)`` and ``f(t)``).

An :class:`AngleFunction` is ``g(theta) = rate * theta + periodic(theta)``, with the
periodic part a Fourier series in integer harmonics of theta (so several inputs keep
integer rate ratios and the motion repeats every 2 pi of theta), given by

- coefficients: ``mean + sum_k cosines[k-1] cos(k theta) + sines[k-1] sin(k theta)``;
- samples of g on a uniform grid ``theta_j = 2 pi j / N`` (a table over one turn of the
  crank, e.g. a piston gas force), read as their trigonometric interpolant (for even N the
  Nyquist term is ``cos(N theta / 2)`` only), so its derivatives are exact where the table
  is band-limited;
- a Python callable ``theta -> (g, g', g'')`` (arrays of theta's shape), checked for
  periodicity of g' and g'' and for derivatives that match g.

Why a function of theta: with ``q^r = g(omega t)`` the input rates are ``omega g'`` and
``omega^2 g''``, so velocities still scale with omega and accelerations with omega^2, and
the linearized equations stay polynomials in omega (``OmegaSplitModel``). A load that is a
function of theta alone carries no power of omega.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import InputError

__all__ = ["AngleFunction", "angle_function"]

CHECK_ANGLES = 7          # angles (rad) at which a callable's derivatives are checked
DERIVATIVE_RTOL = 1e-6    # central differences against the callable's g' and g''
PERIODIC_RTOL = 1e-9      # g'(2 pi) = g'(0), g''(2 pi) = g''(0) for a callable


@dataclass(frozen=True, eq=False)
class AngleFunction:
    """``g(theta) = rate * theta + mean + sum_k a_k cos k theta + b_k sin k theta`` or a
    callable (module docstring); units those of the quantity (rad, m, N, N m) per rad of theta.

    Calling it with angles theta (any shape, rad) returns (g, g', g''), each of theta's shape."""

    rate: float = 0.0
    mean: float = 0.0
    cosines: np.ndarray = field(default_factory=lambda: np.zeros(0))
    sines: np.ndarray = field(default_factory=lambda: np.zeros(0))
    function: Callable | None = None

    @property
    def is_linear(self) -> bool:
        """True for ``g = rate * theta + mean`` (the constant-speed input of eq. 2)."""
        return self.function is None and not (np.any(self.cosines) or np.any(self.sines))

    def __call__(self, theta):
        theta = np.asarray(theta, dtype=float)
        if self.function is not None:
            return _call(self.function, theta)
        g = self.rate * theta + self.mean
        dg = np.full_like(theta, self.rate)
        ddg = np.zeros_like(theta)
        for k, (a, b) in enumerate(zip(self.cosines, self.sines), start=1):
            c, s = np.cos(k * theta), np.sin(k * theta)
            g = g + a * c + b * s
            dg = dg + k * (b * c - a * s)
            ddg = ddg - k * k * (a * c + b * s)
        return g, dg, ddg

    @classmethod
    def linear(cls, rate: float) -> "AngleFunction":
        """``g = rate * theta``."""
        return cls(rate=_finite(rate, "rate"))

    @classmethod
    def fourier(cls, cosines=(), sines=(), *, mean: float = 0.0, rate: float = 0.0) -> "AngleFunction":
        """From coefficients of cos(k theta), sin(k theta), k = 1, 2, ... (shorter list padded with 0)."""
        a, b = (np.asarray(v, dtype=float).reshape(-1) for v in (cosines, sines))
        if not (np.isfinite(a).all() and np.isfinite(b).all()):
            raise InputError(f"Fourier coefficients must be finite numbers, got cosines={cosines!r}, sines={sines!r}")
        n = max(a.size, b.size)
        return cls(_finite(rate, "rate"), _finite(mean, "mean"), np.pad(a, (0, n - a.size)), np.pad(b, (0, n - b.size)))

    @classmethod
    def samples(cls, values, *, rate: float = 0.0) -> "AngleFunction":
        """From g at theta_j = 2 pi j / N, j = 0..N-1 (N >= 1), whose periodic part
        ``g - rate * theta`` is read as its trigonometric interpolant."""
        g = np.asarray(values, dtype=float).reshape(-1)
        if g.size == 0 or not np.isfinite(g).all():
            raise InputError("samples must be a non-empty list of finite values of the function at theta_j = "
                             f"2 pi j / N over one turn, got {values!r}")
        rate = _finite(rate, "rate")
        n = g.size
        c = np.fft.rfft(g - rate * 2.0 * np.pi * np.arange(n) / n) / n
        a, b = 2.0 * c.real[1:], -2.0 * c.imag[1:]
        if n % 2 == 0 and n > 1:  # the Nyquist term: cos(N theta / 2) alone
            a[-1], b[-1] = c.real[-1], 0.0
        return cls(rate, float(c.real[0]), a, b)

    @classmethod
    def from_callable(cls, function: Callable) -> "AngleFunction":
        """From ``function(theta) -> (g, g', g'')``; the rate is ``(g(2 pi) - g(0)) / 2 pi``
        (zero when that is round-off).
        Refuses a function whose derivatives are not periodic or do not match g."""
        if not callable(function):
            raise InputError(f"expected a callable theta -> (g, g', g''), got {type(function).__name__}")
        ends = _call(function, np.array([0.0, 2.0 * np.pi]))
        for name, d in (("g'", ends[1]), ("g''", ends[2])):
            if abs(d[1] - d[0]) > PERIODIC_RTOL * max(1.0, np.abs(d).max()):
                raise InputError(f"{name}(2 pi) = {d[1]!r} differs from {name}(0) = {d[0]!r}: a function of the "
                                 "driving angle must have periodic derivatives (g = rate * theta + a 2 pi-periodic part)")
        theta = 2.0 * np.pi * (np.arange(CHECK_ANGLES) + 0.37) / CHECK_ANGLES
        h = 1e-4
        g0, g1, g2 = _call(function, theta)
        (gp, dp, _), (gm, dm, _) = _call(function, theta + h), _call(function, theta - h)
        for name, of, exact, approx, scale in (
                ("g'", "g", g1, (gp - gm) / (2 * h), np.abs(g0).max() + np.abs(g1).max()),
                ("g''", "g'", g2, (dp - dm) / (2 * h), np.abs(g1).max() + np.abs(g2).max())):
            err = np.abs(exact - approx).max()
            if err > DERIVATIVE_RTOL * max(scale, 1e-300) + 1e-12:
                raise InputError(f"the callable's {name} differs from central differences of its {of} by {err:.3g}: "
                                 "return (g, dg/dtheta, d2g/dtheta2) at the angles given")
        growth = float(ends[0][1] - ends[0][0])  # a periodic function's round-off is no rate
        periodic = abs(growth) <= PERIODIC_RTOL * max(1.0, float(np.abs(ends[0]).max()))
        return cls(rate=0.0 if periodic else growth / (2.0 * np.pi), function=function)


def angle_function(value, what: str) -> AngleFunction:
    """An AngleFunction from a number (a constant, or a rate for a motion: the caller
    decides), an AngleFunction, or a callable; ``what`` names it in errors."""
    if isinstance(value, AngleFunction):
        return value
    if callable(value):
        return AngleFunction.from_callable(value)
    raise InputError(f"{what}: expected an AngleFunction (AngleFunction.fourier / .samples / .from_callable) or "
                     f"a callable theta -> (g, g', g''), got {type(value).__name__}")


def _call(function, theta: np.ndarray):
    try:
        out = function(theta)
        g, dg, ddg = (np.broadcast_to(np.asarray(v, dtype=float), theta.shape) for v in out)
    except (TypeError, ValueError) as exc:
        raise InputError(f"a function of the driving angle must return (g, g', g'') with the shape of theta "
                         f"{theta.shape}: {exc}") from None
    if not (np.isfinite(g).all() and np.isfinite(dg).all() and np.isfinite(ddg).all()):
        raise InputError("a function of the driving angle returned non-finite values")
    return g, dg, ddg


def _finite(value, name: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = float("nan")
    if not np.isfinite(v):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    return v
