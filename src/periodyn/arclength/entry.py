"""``continuation``: the pseudo-arc-length branch (:func:`driver.trace_branch`) with its special
points checked as ``ContinuationOptions.confirm`` asks (:func:`confirm.confirm_special_points`:
True runs the truncation check, then direct integration; "truncation" the first alone)."""

from __future__ import annotations

from functools import wraps

from .branch import Branch
from .confirm import confirm_special_points
from .driver import trace_branch

__all__ = ["continuation"]


@wraps(trace_branch)
def continuation(*args, **kwargs) -> Branch:
    branch = trace_branch(*args, **kwargs)
    confirm = branch.options.get("confirm", False)
    return confirm_special_points(branch, integrate=confirm is True) if confirm else branch
