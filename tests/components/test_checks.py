"""The parameter checks the cores share (components/checks.py): one sentence naming the first bad
parameter, positive before non-negative, NaN failing both."""
import math
from types import SimpleNamespace

import pytest

from musclesim.components.checks import require


@pytest.mark.parametrize("values, match", [
    ({"m": 0.0, "c": 1.0}, r"m must be positive \(got 0.0\)"),
    ({"m": -1.0, "c": -1.0}, "m must be positive"),  # the positive ones first
    ({"m": 1.0, "c": -0.5}, r"c must be non-negative \(got -0.5\)"),
    ({"m": math.nan, "c": 1.0}, "m must be positive"),
    ({"m": 1.0, "c": math.nan}, "c must be non-negative"),
])
def test_the_first_bad_parameter_is_named(values, match):
    with pytest.raises(ValueError, match=match):
        require(SimpleNamespace(**values), positive=["m"], non_negative=["c"])


def test_good_values_pass_and_zero_is_non_negative():
    assert require(SimpleNamespace(m=1e-12, c=0.0), positive=["m"], non_negative=["c"]) is None
    assert require(SimpleNamespace(m=-1.0)) is None  # nothing asked, nothing checked
