"""musclesim.fmu.units: every unit's SI base-unit exponents, derived by hand from its definition,
and the UnitDefinitions element a slave writes."""
import pytest

from musclesim.fmu.units import DISPLAY_UNITS, UNITS, unit_definitions

# each derived unit from units already checked: N = kg m / s2, Pa = N / m2, J = N m, W = J / s,
# V = W / A, Ohm = V / A, H = Ohm s
BY_HAND = {"N": {"kg": 1, "m": 1, "s": -2}, "Pa": {"kg": 1, "m": -1, "s": -2},
           "W": {"kg": 1, "m": 2, "s": -3}, "V": {"kg": 1, "m": 2, "s": -3, "A": -1},
           "Ohm": {"kg": 1, "m": 2, "s": -3, "A": -2}, "H": {"kg": 1, "m": 2, "s": -2, "A": -2},
           "J/(kg.K)": {"m": 2, "s": -2, "K": -1}, "m3/(s.Pa)": {"m": 4, "kg": -1, "s": 1},
           "W/(m2.K)": {"kg": 1, "s": -3, "K": -1}, "Ohm.m": {"kg": 1, "m": 3, "s": -3, "A": -2},
           "1": {}}


@pytest.mark.parametrize("unit", sorted(BY_HAND))
def test_a_derived_unit_has_the_exponents_of_its_definition(unit):
    assert UNITS[unit] == BY_HAND[unit]


def test_no_exponent_is_zero_and_every_base_is_an_si_base():
    for unit, exponents in UNITS.items():
        assert 0 not in exponents.values(), unit
        assert set(exponents) <= {"kg", "m", "s", "A", "K", "rad"}, unit


def test_every_display_unit_shows_a_unit_of_the_table():
    for name, (unit, factor, offset) in DISPLAY_UNITS.items():
        assert unit in UNITS and factor > 0, name
    assert DISPLAY_UNITS["degC"][1] * 300.0 + DISPLAY_UNITS["degC"][2] == pytest.approx(26.85)


def test_unit_definitions_lists_the_used_units_sorted_with_their_display_units():
    element = unit_definitions({"Pa", "s", "K"}, {"K": "degC", "Pa": "kPa"})
    assert [u.get("name") for u in element] == ["K", "Pa", "s"]
    pa = element[1]
    assert pa.find("BaseUnit").attrib == {"kg": "1", "m": "-1", "s": "-2"}
    assert pa.find("DisplayUnit").attrib == {"name": "kPa", "factor": "0.001", "offset": "0.0"}
    assert element[2].find("DisplayUnit") is None
    with pytest.raises(ValueError, match="display unit mm is not one of K"):
        unit_definitions({"K"}, {"K": "mm"})
