"""Results must not drift: compare with the reviewed golden files at rtol 1e-8
(regenerate with ``PYTHONPATH=src python -m tests.regression.goldens [case ...]`` and review
the diff; the cases are listed in goldens.py)."""

import json

import numpy as np
import pytest

from .goldens import CASES, GOLDEN


def _exact(value) -> bool:
    """Strings and booleans (also in lists) are compared exactly, numbers at rtol 1e-8."""
    if isinstance(value, list):
        return any(_exact(v) for v in value)
    return isinstance(value, (str, bool))


def test_every_case_has_a_golden_file_and_every_file_a_case():
    assert sorted(p.stem for p in GOLDEN.glob("*.json")) == sorted(CASES)


@pytest.mark.parametrize("name", sorted(CASES))
def test_matches_golden(name):
    expected = json.loads((GOLDEN / f"{name}.json").read_text())
    actual = json.loads(json.dumps(CASES[name]()))  # the same JSON round trip as the stored file
    assert expected.keys() == actual.keys()
    for key in expected:
        if _exact(expected[key]):
            assert actual[key] == expected[key], key
        else:
            np.testing.assert_allclose(actual[key], expected[key], rtol=1e-8, atol=1e-14, err_msg=key)
