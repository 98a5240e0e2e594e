"""Checks of study-file values: each failure is an InputError that starts with the file
name and the table and says what to change (used by every study kind); what every parsed
study file has (:class:`FileSpec`); type checks of builder keywords."""

from __future__ import annotations

import difflib
import inspect
import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..errors import InputError

__all__ = ["Checker", "FileSpec", "kind", "MAX_POINTS", "FIXED_UNITS", "builder_parameters", "parameter_check"]

MAX_POINTS = 10_000_000
#: Speed units with a fixed factor to rad/s.
FIXED_UNITS = {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0, "Hz": 2.0 * math.pi}


@dataclass(frozen=True)
class FileSpec:
    """What every validated sweep file has: where it came from (source path, name = stem,
    text) and its [model] (example name, builder, [model.parameters])."""

    source: str
    name: str
    text: str
    description: str
    example: str
    builder: Callable = field(repr=False)
    parameters: dict[str, Any]

    @property
    def inputs(self) -> dict:
        """Files the study reads besides its own, parsed (part of its cache fingerprint)."""
        return {}

    def extent(self, omega=None) -> list | None:
        """The range (start, stop, num) replacing the file's, as it changes the result
        (part of the cache fingerprint); None keeps the file's."""
        return None if omega is None else [float(v) for v in omega]


class Checker:
    """Raises InputError prefixed with the file and table."""

    def __init__(self, source: str):
        self.source = source

    def fail(self, where: str, message: str):
        raise InputError(f"{self.source}: {where}: {message}")

    def keys(self, table: dict, where: str, allowed: tuple[str, ...], required: tuple[str, ...] = ()) -> None:
        for key in table:
            if key not in allowed:
                near = difflib.get_close_matches(key, allowed, n=1, cutoff=0.6)
                hint = f"did you mean '{near[0]}'?" if near else f"valid keys: {', '.join(allowed)}"
                self.fail(where, f"unknown key '{key}'; {hint}")
        for key in required:
            if key not in table:
                self.fail(where, f"missing required key '{key}'")

    def table(self, value, where: str) -> dict:
        if not isinstance(value, dict):
            self.fail(where, f"must be a table ({{...}} or a [section]), got {kind(value)}")
        return value

    def number(self, value, where: str, *, positive: bool = False, nonnegative: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(where, f"must be a number, got {kind(value)}")
        if not math.isfinite(value):
            self.fail(where, f"must be finite, got {value!r}")
        if positive and value <= 0:
            self.fail(where, f"must be positive, got {value!r}")
        if nonnegative and value < 0:
            self.fail(where, f"must be >= 0, got {value!r}")
        return float(value)

    def integer(self, value, where: str, minimum: int | None = None) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            self.fail(where, f"must be an integer, got {kind(value)}")
        if minimum is not None and value < minimum:
            self.fail(where, f"must be an integer >= {minimum}, got {value!r}")
        return value

    def boolean(self, value, where: str) -> bool:
        if not isinstance(value, bool):
            self.fail(where, f"must be true or false, got {kind(value)}")
        return value

    def string(self, value, where: str) -> str:
        if not isinstance(value, str):
            self.fail(where, f"must be a string, got {kind(value)}")
        return value

    def values(self, value, where: str, check: Callable[[Any, str], Any]) -> list:
        """A range {start, stop, num} or a non-empty list, each entry passed to ``check``."""
        if isinstance(value, dict):
            self.keys(value, where, ("start", "stop", "num"), ("start", "stop", "num"))
            start = check(value["start"], f"{where}.start")
            stop = check(value["stop"], f"{where}.stop")
            num = self.integer(value["num"], f"{where}.num", 1)
            if num > MAX_POINTS:
                self.fail(f"{where}.num", f"{num} points is more than {MAX_POINTS}; split the sweep")
            return [float(v) for v in np.linspace(start, stop, num)]
        if not isinstance(value, list) or not value:
            self.fail(where, f"must be a non-empty list of values or a range {{start, stop, num}}, got {kind(value)}")
        return [check(v, f"{where}[{i}]") for i, v in enumerate(value)]


def parameter_check(check: Checker, parameter: inspect.Parameter) -> Callable[[Any, str], Any]:
    """Type check for one builder keyword from its default value (or annotation)."""
    default = parameter.default
    annotation = str(parameter.annotation)
    if isinstance(default, bool) or annotation == "bool":
        return check.boolean
    if isinstance(default, int) or annotation == "int":
        return check.integer
    if isinstance(default, float) or annotation == "float":
        return check.number
    if isinstance(default, str) or annotation == "str":
        return check.string
    return lambda v, where: v


def builder_parameters(builder: Callable) -> dict[str, inspect.Parameter]:
    """The keyword parameters of a model builder by name."""
    return {name: p for name, p in inspect.signature(builder).parameters.items()
            if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)}


def kind(value) -> str:
    """'an integer (3)', 'a table', ... for messages."""
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, list):
        return "a list"
    names = {bool: "a boolean", int: "an integer", float: "a number", str: "a string"}
    return f"{names.get(type(value), type(value).__name__)} ({value!r})"

