"""Option objects: small frozen dataclasses that validate themselves on construction (an
:class:`~periodyn.errors.InputError` naming the field and the fix), and the one rule by
which a function takes them: ``options=`` an object, keyword values override its fields
(:func:`merge_options`; an unknown keyword is refused by name).

:class:`IntegrationOptions` is how a time integration runs (integrator, tolerances, largest
step, steps of the fixed-step map); ``periodyn.shooting`` and ``periodyn.integrate_stiff``
take it.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from ..errors import InputError

__all__ = ["INTEGRATORS", "IntegrationOptions", "STEPS", "check_count", "check_positive", "merge_options"]

INTEGRATORS = ("DOP853", "Radau", "BDF", "implicit")
#: default steps per period of the fixed-step map: slider-crank at 150 rad/s (its finest-resolved
#: speed), extrapolated harmonics 7e-5 from DOP853 relative to the largest, estimate 8e-4
#: (``periodyn.nonlinear.implicit``)
STEPS = 256


def check_count(owner: str, name: str, value, minimum: int, fix: str = "") -> int:
    """``value`` as an int >= minimum, else InputError naming ``owner.name`` and the fix."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(f"{owner}.{name} must be an integer >= {minimum}, got {value!r}" + (f"; {fix}" if fix else ""))
    return int(value)


def check_positive(owner: str, name: str, value, fix: str = "") -> float:
    """``value`` as a finite float > 0, else InputError naming ``owner.name`` and the fix."""
    ok = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)
    if not ok or not np.isfinite(value) or value <= 0:
        raise InputError(f"{owner}.{name} must be a finite number > 0, got {value!r}" + (f"; {fix}" if fix else ""))
    return float(value)


def merge_options(cls, options, values: dict, where: str, aliases: dict | None = None):
    """``options`` (an instance of the frozen dataclass ``cls``, or None for its defaults)
    with the keyword ``values`` of a call to ``where`` replacing its fields. aliases: {keyword:
    (field, transform)} for keywords that set a field of a nested option object. An unknown
    keyword or an ``options`` of another type raises InputError naming it and the choices."""
    if options is None:
        options = cls()
    elif not isinstance(options, cls):
        raise InputError(f"{where}(options=...) must be a periodyn.{cls.__name__}, got {type(options).__name__}")
    names = {f.name for f in fields(cls)}
    aliases = aliases or {}
    unknown = sorted(set(values) - names - set(aliases))
    if unknown:
        raise InputError(f"{where}() got unknown keyword(s) {', '.join(map(repr, unknown))}; its options are "
                         f"{', '.join(sorted(names | set(aliases)))} (or options=periodyn.{cls.__name__}(...))")
    direct = {k: v for k, v in values.items() if k in names}
    merged = replace(options, **direct) if direct else options
    for key, value in values.items():
        if key in aliases:
            field, transform = aliases[key]
            merged = replace(merged, **{field: transform(getattr(merged, field), key, value)})
    return merged


@dataclass(frozen=True)
class IntegrationOptions:
    """How a time integration runs.

    integrator: "DOP853" (explicit, adaptive: non-stiff models), "Radau" or "BDF" (implicit,
        adaptive, with the analytic Jacobian: stiff models) or "implicit" (shooting of element
        and rheo-linear models only: ``steps`` trapezoidal steps per period in Numba, the exact
        monodromy of the discrete map); rtol, atol: tolerances of the adaptive integrators
        (atol in the states' units: m, rad, m/s, rad/s); max_step: largest step of the
        adaptive integrators, s (inf: as the error control allows); steps: even steps per
        period of the fixed-step map (>= 8).
    """

    integrator: str = "DOP853"
    rtol: float = 1e-11
    atol: float = 1e-12
    max_step: float = np.inf
    steps: int = STEPS

    def __post_init__(self):
        if self.integrator not in INTEGRATORS:
            raise InputError(f"IntegrationOptions.integrator must be one of {INTEGRATORS}, got {self.integrator!r}: "
                             "'DOP853' for non-stiff systems, 'Radau'/'BDF' or 'implicit' (element models) for "
                             "stiff ones")
        for name in ("rtol", "atol"):
            object.__setattr__(self, name, check_positive("IntegrationOptions", name, getattr(self, name),
                                                          "give a tolerance such as 1e-10"))
        if not (isinstance(self.max_step, (int, float, np.integer, np.floating)) and self.max_step > 0):
            raise InputError("IntegrationOptions.max_step must be a step in s > 0 (inf: no limit), got "
                             f"{self.max_step!r}")
        object.__setattr__(self, "max_step", float(self.max_step))
        steps = check_count("IntegrationOptions", "steps", self.steps, 8, "give an even number of steps per period")
        if steps % 2:
            raise InputError(f"IntegrationOptions.steps must be even (the map halves it), got {steps}; "
                             f"give {steps + 1}")
        object.__setattr__(self, "steps", steps)
