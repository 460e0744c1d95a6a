"""The SMA wire FMUs' ports (components/sma/ports.py): declared once, in order, with their units,
start values and the ambient's calibration; non-finite inputs named."""
import math

import pytest

from musclesim.components.multiplier.slaves import CapstanMultiplier
from musclesim.components.sma import ports, thermal
from musclesim.components.sma.slaves import SmaWire
from musclesim.fmu import Slave


class Wire(Slave):
    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        ports.declare_ports(self, "Load", {"stress": "Stress", "T": "Temperature"})


def test_declares_the_inputs_then_the_outputs_asked_for():
    d = Wire.declarations()
    assert list(d) == ["u", "T_amb", "flange.f", "stress", "T"]
    assert [d[n].causality for n in d] == ["input"] * 3 + ["output"] * 2
    assert [d[n].unit for n in d] == ["1", "K", "N", "Pa", "K"]
    assert (d["T_amb"].default, d["flange.f"].default) == (293.15, ports.LOAD_150G)
    assert d["T_amb"].calibrate is thermal.AMBIENT
    assert d["flange.f"].description == "Load" and d["stress"].depends == ()
    # 150 g on the 127 um wire: 116 MPa (§capstan-multiplier)
    area = thermal.cross_section(thermal.ThermalParams())
    assert ports.LOAD_150G / area == pytest.approx(116e6, rel=5e-3)


@pytest.mark.parametrize("slave", [SmaWire, CapstanMultiplier])
def test_both_wire_fmus_share_the_inputs_and_the_output_units(slave):
    d = slave.declarations()
    ours = Wire.declarations()
    for name in ("u", "T_amb"):
        assert d[name] == ours[name]
    for name, unit in ports.OUTPUT_UNITS.items():
        if name in d:
            assert d[name].unit == unit and d[name].causality == "output"


@pytest.mark.parametrize("bad, name", [((math.nan, 20.0, 1.0), "u"),
                                       ((0.0, math.inf, 1.0), "T_amb"),
                                       ((0.0, 20.0, -math.inf), "flange.f")])
def test_a_non_finite_input_is_named_with_the_time(bad, name):
    with pytest.raises(ValueError, match=rf"input {name} is .* at t = 0.25 s"):
        ports.check_inputs(*bad, 0.25)
    ports.check_inputs(0.0, 20.0, 1.0, 0.25)
