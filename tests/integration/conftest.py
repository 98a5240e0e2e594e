"""Every test collected under tests/integration/ carries the ``jit`` marker (it compiles or
loads kernels in new processes, or runs whole studies), so ``-m "not jit"`` selects the fast
loop without a marker line in each file."""

from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Mark before ``-m`` deselects (tryfirst: this runs ahead of pytest's own selection)."""
    for item in items:
        if HERE in Path(item.path).resolve().parents:
            item.add_marker(pytest.mark.jit)
