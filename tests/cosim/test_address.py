"""musclesim.cosim.address: a Signal and a ParamRef parse from and print to ``"instance.name"``,
the one spelling of each; a malformed string is a ValueError."""
import dataclasses

import pytest

from musclesim.cosim import ParamRef, Signal


@pytest.mark.parametrize("text, instance, name", [
    ("wire.T_amb", "wire", "T_amb"),
    ("body.flange_a.s", "body", "flange_a.s"),  # an FMI structured name keeps its dots
    ("mult.segment[1].strain", "mult", "segment[1].strain"),
])
def test_parse_and_print_round_trip(text, instance, name):
    s, p = Signal.parse(text), ParamRef.parse(text)
    assert (s.instance, s.variable) == (instance, name) and str(s) == text
    assert (p.instance, p.name) == (instance, name) and str(p) == text
    assert Signal.parse(str(s)) == s and ParamRef.parse(str(p)) == p


@pytest.mark.parametrize("text", ["wire", "wire.", ".T_amb", "", "."])
def test_a_malformed_string_is_a_value_error(text):
    with pytest.raises(ValueError, match="not of the form"):
        Signal.parse(text)
    with pytest.raises(ValueError, match="parameter .* is not of the form"):
        ParamRef.parse(text)


@pytest.mark.parametrize("value", [None, 3, ("wire", "T")])
def test_a_non_string_is_a_value_error(value):
    with pytest.raises(ValueError, match="is not a string"):
        Signal.parse(value)


def test_addresses_are_frozen_ordered_and_hashable():
    a, b = Signal("a", "y"), Signal("b", "u")
    assert sorted([b, a]) == [a, b] and {a: 1}[Signal("a", "y")] == 1
    assert Signal("a", "y") != ParamRef("a", "y")  # a signal is not a parameter
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.instance = "c"
