"""Temperature control of the SMA wire (§temperature-control): the shipped scenarios, shortened.

Topology::

    reference --r--> pid --u--> wire --T--> thermocouple --T_meas--> pid (y)
    load --flange.f--> wire
"""
import numpy as np
import pytest

from musclesim.cosim import master, scenario, Signal

from conftest import SCENARIOS

S = Signal.parse


def run(name, stop_time, fmu_dir):
    s = scenario.load(SCENARIOS / f"{name}.toml", stop_time=stop_time)
    res = master.Master(s, fmu_dir).run()
    assert res.error is None, res.error
    return s, res


def test_regulation_settles_on_the_reference(fmu_dir):
    s, res = run("sma-temperature-regulation", 4.0, fmu_dir)
    assert s.instances["pid"].parameters["Kp[11]"] > 0  # gains read from the design's table
    late = res.time >= 3.0
    assert np.abs(res[S("pid.e")][late]).max() < 0.01  # K
    assert res[S("wire.T")][-1] == pytest.approx(348.15, abs=0.01)
    assert 0 <= res[S("pid.y")].min() and res[S("pid.y")].max() <= 2.5  # heating only, within 2.5 V


def test_tracking_follows_the_sine_and_the_wire_contracts(fmu_dir):
    _, res = run("sma-temperature-tracking", 8.0, fmu_dir)
    late = res.time >= 2.0
    assert np.sqrt(np.mean(res[S("pid.e")][late] ** 2)) < 0.3  # K
    assert res[S("wire.strain")].max() > 0.03  # heated through the transformation (to 102 C by 8 s)


def test_stress_outside_the_data_set_is_clamped_with_one_warning(fmu_dir):
    s = scenario.load(SCENARIOS / "sma-temperature-regulation.toml", ["load.offset=3.0"],
                      stop_time=0.5)  # 3 N on 127 um: 237 MPa, above the wire's 60..200 MPa
    res = master.Master(s, fmu_dir).run()
    assert res.error is None
    assert len(res.warnings) == 1
    assert res.warnings[0].startswith("wire: stress 2.36823e+08 Pa at t = 0 s is outside")
    assert "clamped to 2e+08 Pa" in res.warnings[0]
