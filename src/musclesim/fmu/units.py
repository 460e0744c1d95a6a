"""The units a musclesim FMU's variables carry: `UNITS`, every SI unit a variable may declare with
its base-unit exponents, and `DISPLAY_UNITS`, the other units a tool may show a value in (FMI 2.0
``UnitDefinitions``, which `unit_definitions` writes for `musclesim.fmu.Slave`). `PLAUSIBLE` and
`DIFFERENCES` are the values a parameter of a unit may plausibly take (a `Plausible` range) where
its declaration says nothing else, `QUANTITIES` those of quantities a declaration names, and
`SLIPS` the other units a value is likely written in by
mistake: a scenario's values are checked against them before a run (`musclesim.cosim`).

Shipped inside every FMU with the rest of `musclesim.fmu`: the standard library only.
"""
from __future__ import annotations

from typing import NamedTuple
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
    "K/Pa": {"K": 1, "kg": -1, "m": 1, "s": 2},
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



class Plausible(NamedTuple):
    """The values a parameter plausibly takes, `lo` to `hi` in its SI unit, and `what` it is
    ("a temperature"; "" for a range a declaration states, whose parameter's name says it). Wide
    on purpose: it catches a value written in another unit (Celsius, mm, MPa, g) or an absurd one
    (1e-300 kg), not a poor choice; a core's own ``check`` says what is invalid."""

    lo: float
    hi: float
    what: str = ""


# the plausible values of a parameter of each unit, unless its declaration says otherwise
# (`musclesim.fmu.declare`'s `plausible`); a unit not here has no default range
PLAUSIBLE: dict[str, Plausible] = {
    "K": Plausible(150.0, 1500.0, "a temperature"),  # liquid-nitrogen cold to red-hot metal
    "m": Plausible(0.0, 10.0, "a length"),  # a muscle, a robot, a bench: at most metres
    "m2": Plausible(0.0, 1.0, "an area"),
    "m3": Plausible(0.0, 1.0, "a volume"),
    "kg": Plausible(1e-7, 100.0, "a mass"),  # a tenth of a milligram (a foot's tip) to 100 kg
    "s": Plausible(0.0, 1e6, "a time"),  # up to 11 days
    "Hz": Plausible(0.0, 1e6, "a frequency"),
    "Pa": Plausible(1e3, 1e12, "a stress or modulus"),  # kPa of soft matter to TPa (diamond)
    "kg/m3": Plausible(100.0, 3e4, "a density"),  # a foam to osmium: no gas here
    "J/(kg.K)": Plausible(10.0, 2e4, "a specific heat"),
    "m/s2": Plausible(0.0, 1e3, "an acceleration"),
}

# where a declaration says its parameter is a difference (``plausible="difference"``: a bias, a
# shift, an amplitude, a noise level), the plausible values of a difference of each unit; a
# temperature difference has no Celsius slip (1 K = 1 C)
DIFFERENCES: dict[str, Plausible] = {
    "K": Plausible(-500.0, 500.0, "a temperature difference"),
    "m": Plausible(-10.0, 10.0, "a displacement"),
    "N": Plausible(-1e4, 1e4, "a force difference"),
    "Pa": Plausible(-1e9, 1e9, "a pressure or stress difference"),
}

# quantities whose plausible values differ from their unit's, which a declaration names
# (``plausible="gauge pressure"``)
QUANTITIES: dict[str, Plausible] = {
    "gauge pressure": Plausible(-101325.0, 1e7, "a gauge pressure"),  # a full vacuum to 100 bar
    # a pressure that inflates an actuator: at least 100 Pa, so that kPa written as Pa is caught
    "inflating pressure": Plausible(100.0, 1e7, "an inflating gauge pressure"),
    # a wire's tensile stress: 1 MPa (slack) to 2 GPa (beyond NiTi's ultimate strength)
    "wire stress": Plausible(1e6, 2e9, "a wire's stress"),
}

# the units a value of each unit is likely written in by mistake: (name, factor to the SI unit);
# a refused value whose conversion lands in range is shown converted (the nearest the default)
SLIPS: dict[str, tuple[tuple[str, float], ...]] = {
    "m": (("mm", 1e-3), ("um", 1e-6)),
    "m2": (("mm2", 1e-6),),
    "m3": (("cm3", 1e-6), ("mm3", 1e-9)),
    "kg": (("g", 1e-3), ("mg", 1e-6)),
    "s": (("ms", 1e-3),),
    "Pa": (("kPa", 1e3), ("MPa", 1e6), ("GPa", 1e9)),
    "kg/m3": (("g/cm3", 1e3),),
}
CELSIUS = 273.15  # K at 0 C: a temperature written in Celsius is this much too low


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
