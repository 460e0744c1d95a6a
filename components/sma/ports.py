"""The ports of an SMA wire's FMU, declared once for the SmaWire and the CapstanMultiplier: the
electrical input, the ambient and the load in, temperature, strain, contraction, stress,
resistance and power out (`declare_ports`), and the check of the inputs at every step
(`check_inputs`)."""
from __future__ import annotations

import math

from musclesim.components.sma import thermal
from musclesim.fmu import Slave

__all__ = ["LOAD_150G", "OUTPUT_UNITS", "declare_ports", "check_inputs"]

LOAD_150G = 0.150 * 9.80665  # N, the 150 g weight of the multiplier tests (§capstan-multiplier):
#                              116 MPa on the 127 um wire
# the unit of each output a wire FMU may declare
OUTPUT_UNITS = {"T": "K", "strain": "1", "flange.s": "m", "stress": "Pa", "R": "Ohm", "P": "W",
                "xi": "1"}


def declare_ports(slave: Slave, load: str, outputs: dict[str, str]) -> None:
    """Declare on `slave` the inputs u, T_amb and flange.f (`load`: the load's description), then
    `outputs`, {name: description} in their order, each with its unit of `OUTPUT_UNITS`."""
    slave.input("u", 0.0, "1", "Electrical input: voltage across the wire [V], or current "
                "through it [A] when drive_current = 1")
    slave.input("T_amb", 293.15, "K", "Ambient air temperature (assumption: a 20 C "
                "laboratory)", source="§thermal-model", calibrate=thermal.AMBIENT)
    slave.input("flange.f", LOAD_150G, "N", load, source="§capstan-multiplier")
    for name, description in outputs.items():
        slave.output(name, OUTPUT_UNITS[name], description)


def check_inputs(u: float, T_amb: float, f: float, t: float) -> None:
    """Raise ValueError naming the first of the inputs `u`, `T_amb`, flange.f (`f`) that is not
    finite at time `t` [s]."""
    for name, value in (("u", u), ("T_amb", T_amb), ("flange.f", f)):
        if not math.isfinite(value):
            raise ValueError(f"input {name} is {value!r} at t = {t:g} s")
