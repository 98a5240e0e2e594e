"""Option objects of the pointwise non-linear solvers: :class:`ShootingOptions` of
``periodyn.shooting`` and :class:`IHBOptions` of ``periodyn.ihb`` (frozen, validated on
construction; the keywords of those functions override their fields, ``numerics.options``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace

from ..errors import InputError
from ..numerics.options import IntegrationOptions, check_count, check_positive, merge_options
from ..stability.methods import check_method

__all__ = ["IHBOptions", "ShootingOptions", "ihb_options", "shooting_options"]


@dataclass(frozen=True)
class ShootingOptions:
    """How ``periodyn.shooting`` solves.

    subharmonic: nu (orbit period 2 pi nu / omega); settle_periods: periods integrated
    (loose tolerance, explicit method, stopping early once settled) before Newton; None:
    from rest, settle up to 400 periods first; from a given guess, Newton first and, when it
    fails, settle and try again. segments: N >= 1 (multiple shooting for long periods or
    strongly unstable orbits). cyclic: names or indices of angle coordinates compared modulo
    2 pi. tol: residual max-norm of the independent states (m, rad, m/s, rad/s); max_iter:
    Newton iterations; samples: orbit samples of the result's spectra; integration: the
    :class:`IntegrationOptions` of the period integrations (default DOP853 at rtol 1e-11).
    """

    subharmonic: int = 1
    settle_periods: int | None = None
    segments: int = 1
    cyclic: tuple = ()
    tol: float = 1e-9
    max_iter: int = 30
    samples: int = 128
    integration: IntegrationOptions = IntegrationOptions()

    def __post_init__(self):
        own = "ShootingOptions"
        set_ = lambda name, v: object.__setattr__(self, name, v)  # noqa: E731
        set_("subharmonic", check_count(own, "subharmonic", self.subharmonic, 1))
        set_("segments", check_count(own, "segments", self.segments, 1, "1 for single shooting"))
        if self.settle_periods is not None:
            set_("settle_periods", check_count(own, "settle_periods", self.settle_periods, 0,
                                               "or None for the default (module docstring)"))
        set_("tol", check_positive(own, "tol", self.tol, "give a residual such as 1e-9"))
        set_("max_iter", check_count(own, "max_iter", self.max_iter, 1))
        set_("samples", check_count(own, "samples", self.samples, 3, "the result's spectra need 2H + 1 samples"))
        cyclic = (self.cyclic,) if isinstance(self.cyclic, (str, int)) else self.cyclic
        try:
            set_("cyclic", tuple(cyclic))
        except TypeError:
            raise InputError(f"{own}.cyclic must be names or indices of angle coordinates, "
                             f"got {self.cyclic!r}") from None
        if not isinstance(self.integration, IntegrationOptions):
            raise InputError(f"{own}.integration must be a periodyn.IntegrationOptions, got "
                             f"{type(self.integration).__name__}")
        if self.integration.integrator == "implicit" and (self.segments != 1 or self.cyclic):
            raise InputError("integrator='implicit' shoots one segment without cyclic coordinates; use segments=1 "
                             "and cyclic=(), or an adaptive integrator ('DOP853', 'Radau', 'BDF')")


@dataclass(frozen=True)
class IHBOptions:
    """How ``periodyn.ihb`` solves.

    samples: p (None: the anti-aliasing default of ``ihb_solver.default_samples``);
    subharmonic: nu (orbit period 2 pi nu / omega); tol: residual max-norm (N, N m, m, rad);
    max_iter: Newton iterations; stability: a stability method of
    :mod:`periodyn.stability.methods` ("magnus", "monodromy", "hill", "dense", "sparse",
    "auto", ...) for the orbit's Floquet exponents, or None (none computed).
    """

    samples: int | None = None
    subharmonic: int = 1
    tol: float = 1e-8
    max_iter: int = 30
    stability: str | None = "magnus"

    def __post_init__(self):
        own = "IHBOptions"
        if self.samples is not None:
            object.__setattr__(self, "samples", check_count(own, "samples", self.samples, 5,
                                                            "or None for the anti-aliasing default"))
        object.__setattr__(self, "subharmonic", check_count(own, "subharmonic", self.subharmonic, 1))
        object.__setattr__(self, "tol", check_positive(own, "tol", self.tol, "give a residual such as 1e-8"))
        object.__setattr__(self, "max_iter", check_count(own, "max_iter", self.max_iter, 1))
        if self.stability is not None:
            try:
                check_method(self.stability)
            except InputError as exc:
                raise InputError(f"{own}.stability: {exc}, or None for no exponents") from None


def _integration(name: str):
    """Alias transform: keyword ``name`` sets that field of ShootingOptions.integration."""
    return "integration", lambda integ, key, value: replace(integ, **{name: value})


_SHOOTING_ALIASES = {name: _integration(name) for name in ("integrator", "rtol", "atol", "max_step", "steps")}


def shooting_options(options: ShootingOptions | None, values: dict) -> ShootingOptions:
    """ShootingOptions of a ``shooting`` call: ``options`` with the keyword values over it
    (the integration fields integrator, rtol, atol, max_step and steps flat; ``method``, the
    deprecated spelling of ``integrator``, warns)."""
    values = dict(values)
    if "method" in values:
        method = values.pop("method")
        warnings.warn("shooting(method=...) is deprecated and goes in the next release; pass "
                      f"integrator={method!r}", DeprecationWarning, stacklevel=3)
        if values.setdefault("integrator", method) != method:
            raise InputError(f"integrator={values['integrator']!r} and method={method!r} disagree; "
                             "pass only integrator=")
    return merge_options(ShootingOptions, options, values, "shooting", _SHOOTING_ALIASES)


def ihb_options(options: IHBOptions | None, values: dict) -> IHBOptions:
    """IHBOptions of an ``ihb`` call: ``options`` with the keyword values over it."""
    return merge_options(IHBOptions, options, values, "ihb")
