"""Argument checks shared by the example builders."""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["require_physical"]


def require_physical(builder: str, positive: dict, non_negative: dict, finite: dict) -> None:
    """Refuse builder arguments that would build another system: ``positive`` (lengths,
    masses, frequencies) finite and > 0, ``non_negative`` (stiffnesses, dampings, gravity)
    finite and >= 0, ``finite`` (load amplitudes) finite; the message names the argument."""
    for rule, values, test in (("finite and > 0", positive, lambda v: v > 0),
                               ("finite and >= 0", non_negative, lambda v: v >= 0),
                               ("finite", finite, lambda v: True)):
        for name, value in values.items():
            if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
                    or not (np.isfinite(value) and test(value)):
                raise InputError(f"{builder}: {name} must be {rule} (a real number in SI units), got {value!r}; "
                                 "a negative length or mass would be solved as another system (e.g. an inverted "
                                 "pendulum)")
