"""Edits of parsed study files for the fuzz tests: TOML text of a Python value, the path of
every leaf of a table, a copy with one leaf replaced, and random junk values."""

from __future__ import annotations

import copy
import json
import math

from hypothesis import strategies as st


def toml_value(value) -> str:
    """Inline TOML of a value (numbers including nan and inf, strings, lists, inline tables)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    if isinstance(value, (int, float, str)):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return "{ " + ", ".join(f"{toml_value(k)} = {toml_value(v)}" for k, v in value.items()) + " }"


def leaves(data, path: tuple = ()) -> list[tuple]:
    """Paths of every value below ``data`` (tables and lists included)."""
    items = data.items() if isinstance(data, dict) else enumerate(data) if isinstance(data, list) else []
    found = [path] if path else []
    for k, v in items:
        found += leaves(v, path + (k,))
    return found


def replaced(data: dict, path: tuple, value) -> dict:
    """A deep copy of ``data`` with the value at ``path`` replaced."""
    data = copy.deepcopy(data)
    table = data
    for key in path[:-1]:
        table = table[key]
    table[path[-1]] = value
    return data


def junk(integers, text):
    """Numbers, booleans, strings and small lists and tables of them."""
    scalars = st.one_of(integers, st.floats(allow_nan=True, allow_infinity=True), st.booleans(), text)
    return st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=3),
                                                         st.dictionaries(text, inner, max_size=3)), max_leaves=6)
