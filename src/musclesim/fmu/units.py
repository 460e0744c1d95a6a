"""The units a musclesim FMU's variables carry: `UNITS`, every SI unit a variable may declare with
its base-unit exponents, and `DISPLAY_UNITS`, the other units a tool may show a value in (FMI 2.0
``UnitDefinitions``, which `unit_definitions` writes for `musclesim.fmu.Slave`).

Shipped inside every FMU with the rest of `musclesim.fmu`: the standard library only.
"""
from __future__ import annotations

from xml.etree.ElementTree import Element, SubElement

# SI base-unit exponents of every unit a variable may carry (FMI 2.0 BaseUnit attributes).
UNITS: dict[str, dict[str, int]] = {
    "m": {"m": 1},
    "m/s": {"m": 1, "s": -1},
    "m/s2": {"m": 1, "s": -2},
    "m2": {"m": 2},
    "m3": {"m": 3},
    "m3/(s.Pa)": {"m": 4, "kg": -1, "s": 1},
    "kg": {"kg": 1},
    "s": {"s": 1},
    "Hz": {"s": -1},
    "rad": {"rad": 1},
    "N": {"kg": 1, "m": 1, "s": -2},
    "N/m": {"kg": 1, "s": -2},
    "N.s/m": {"kg": 1, "s": -1},
    "Pa": {"kg": 1, "m": -1, "s": -2},
    "K": {"K": 1},
    "W": {"kg": 1, "m": 2, "s": -3},
    "V": {"kg": 1, "m": 2, "s": -3, "A": -1},
    "A": {"A": 1},
    "Ohm": {"kg": 1, "m": 2, "s": -3, "A": -2},
    "H": {"kg": 1, "m": 2, "s": -2, "A": -2},
    "N/A": {"kg": 1, "m": 1, "s": -2, "A": -1},
    "1/A": {"A": -1},
    "1/s": {"s": -1},
    "1/rad": {"rad": -1},
    "kg/s": {"kg": 1, "s": -1},
    "kg/m3": {"kg": 1, "m": -3},
    "J/kg": {"m": 2, "s": -2},
    "J/(kg.K)": {"m": 2, "s": -2, "K": -1},
    "W/K": {"kg": 1, "m": 2, "s": -3, "K": -1},
    "W/(m2.K)": {"kg": 1, "s": -3, "K": -1},
    "W/(m.K)": {"kg": 1, "m": 1, "s": -3, "K": -1},
    "Ohm.m": {"kg": 1, "m": 3, "s": -3, "A": -2},
    "1": {},
}

# display units a tool may show a variable in (FMI 2.0 DisplayUnit: shown = factor * value +
# offset): name -> (unit, factor, offset)
DISPLAY_UNITS: dict[str, tuple[str, float, float]] = {
    "degC": ("K", 1.0, -273.15),
    "MPa": ("Pa", 1e-6, 0.0),
    "kPa": ("Pa", 1e-3, 0.0),
    "mm": ("m", 1e3, 0.0),
}


def unit_definitions(used: set[str], display_units: dict[str, str]) -> Element:
    """The ``UnitDefinitions`` element (FMI 2.0 and 3.0 alike) of the units `used`, each shown in
    its display unit in `display_units` (unit -> a name of `DISPLAY_UNITS`) if it has one."""
    units = Element("UnitDefinitions")
    for unit in sorted(used):
        node = SubElement(units, "Unit", name=unit)
        SubElement(node, "BaseUnit", {k: str(e) for k, e in UNITS[unit].items()})
        if unit in display_units:
            name = display_units[unit]
            base, factor, offset = DISPLAY_UNITS[name]
            if base != unit:
                raise ValueError(f"display unit {name} is not one of {unit}")
            SubElement(node, "DisplayUnit", name=name, factor=repr(factor), offset=repr(offset))
    return units
