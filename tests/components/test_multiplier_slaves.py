"""The CapstanMultiplier FMU (components/multiplier/slaves.py, §capstan-multiplier): each segment's
stress, one segment without friction as the straight wire bit for bit."""
import math

import numpy as np
import pytest

from musclesim.components.multiplier.slaves import CapstanMultiplier
from musclesim.components.sma.slaves import SmaWire
from musclesim.components.sma.thermal import ThermalParams, cross_section

from conftest import in_process
from component_runs import OUTPUTS, heat_cool, run_wire

AREA = cross_section(ThermalParams())


def test_each_segment_sees_its_own_capstan_stress(fmu_dir):
    f = 1.47  # N, the 150 g weight: 116 MPa at the load end
    slave = in_process(CapstanMultiplier, "mult")
    r = run_wire(slave, heat_cool(6.0, total=0.5), np.full(500, f),
            names=("segment[1]_stress", "segment[2]_stress", "segment[3]_stress",
                   "segment[4]_stress", "segment[1]_strain", "segment[3]_strain", "stress"))
    e = math.exp(0.0237 * math.pi)
    assert r["segment[3]_stress"][-1] == pytest.approx(f / AREA, rel=1e-15)
    assert r["segment[2]_stress"][-1] == pytest.approx(f * e / AREA, rel=1e-15)
    assert r["segment[1]_stress"][-1] == pytest.approx(f * e * e / AREA, rel=1e-15)
    assert r["segment[4]_stress"][-1] == 0.0  # unused
    assert r["stress"][-1] == f / AREA
    # a higher stress saturates at a larger strain (the reference wire's eps_max grows with it)
    assert r["segment[1]_strain"][-1] > r["segment[3]_strain"][-1] > 0.03


@pytest.mark.parametrize("drive", [0.0, 1.0], ids=["voltage", "current"])
@pytest.mark.parametrize("hysteresis", [0.0, 1.0], ids=["reference-wire", "forc-data-set-1"])
def test_one_segment_without_friction_is_the_straight_wire_bit_for_bit(drive, hysteresis):
    length = 0.214
    u = heat_cool(0.5 if drive else 6.0)
    f = np.linspace(1.3, 1.8, len(u))  # 103-142 MPa: clamped at both data sets' ends, interpolated
    params = {"length": length, "drive_current": drive, "hysteresis": hysteresis, "T_init": 303.15}
    wire = run_wire(in_process(SmaWire, "wire", **params), u, f)
    mult = run_wire(in_process(CapstanMultiplier, "mult", n_segments=1.0, mu_f=0.0, **params), u, f)
    for name in OUTPUTS:
        assert np.array_equal(wire[name], mult[name]), name
    assert wire["strain"].max() > 0.03  # the run transformed the wire
