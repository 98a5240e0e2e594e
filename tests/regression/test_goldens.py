"""Results must not drift: compare with the reviewed golden files at rtol 1e-8
(regenerate with ``python -m tests.regression.goldens`` and review the diff)."""

import json

import numpy as np
import pytest

from .goldens import CASES, GOLDEN


@pytest.mark.parametrize("name", sorted(CASES))
def test_matches_golden(name):
    expected = json.loads((GOLDEN / f"{name}.json").read_text())
    actual = CASES[name]()
    assert expected.keys() == actual.keys()
    for key in expected:
        if key == "method":
            assert actual[key] == expected[key]
        else:
            np.testing.assert_allclose(actual[key], expected[key], rtol=1e-8, atol=1e-14, err_msg=key)
