"""The fast-actuation scenarios of §bending-actuator through the FMUs and the master: the bending
actuator with one wire pulsed and with both alternating, and the quadruped walking.

    driveA --u--> actuator <--u-- driveB          sequencer --8 x u--> leg1..leg4 --tip--> body
"""
import pytest

from musclesim.analysis import bending
from musclesim.cosim import master, results, scenario, Signal

from conftest import SCENARIOS

S = Signal.parse


def simulate(fmu_dir, name, overrides=()):
    s = scenario.load(SCENARIOS / f"{name}.toml", overrides)
    res = master.Master(s, fmu_dir).run()
    assert res.error is None, res.error
    return res, results.compute_metrics(res, s.metrics)


@pytest.fixture(scope="module")
def runs(fmu_dir):
    """The three scenarios as committed (4 s each)."""
    return {name: simulate(fmu_dir, name)
            for name in ("bending-one-wire", "bending-alternating", "quadruped-walk")}


def test_one_wire_bends_toward_itself_within_its_band(runs):
    res, m = runs["bending-one-wire"]
    assert 0 < m["tip_min"] < m["tip_max"]  # wire A alone: always toward A
    assert m["tip_to_tip"] == pytest.approx(m["tip_max"] - m["tip_min"])
    lo, hi = bending()["thermal"]["band"]  # the linear model's band of the same pulses
    assert m["wireA_T_min"] - 273.15 == pytest.approx(lo, abs=3.0)
    assert m["wireA_T_max"] - 273.15 == pytest.approx(hi, abs=3.0)
    assert res[S("actuator.wireB.T")].max() == pytest.approx(293.15)  # B is not heated


def test_alternating_wires_swing_both_ways_and_further(runs):
    _, one = runs["bending-one-wire"]
    _, alt = runs["bending-alternating"]
    assert alt["tip_min"] == pytest.approx(-alt["tip_max"], rel=0.02)
    assert alt["tip_to_tip"] > 1.2 * one["tip_to_tip"]
    for side in ("A", "B"):  # the same band in each wire, as wire A's alone
        assert alt[f"wire{side}_T_min"] == pytest.approx(one["wireA_T_min"], abs=0.05)
        assert alt[f"wire{side}_T_max"] == pytest.approx(one["wireA_T_max"], abs=0.05)


def test_quadruped_walks_forward(runs):
    res, m = runs["quadruped-walk"]
    assert 2e-4 < m["mean_speed"] < 5e-3  # m/s: forward, at most a few strokes per pulse
    assert res[S("body.x")][-1] == pytest.approx(m["distance"])
