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


def _clamping_run(n=800):
    """Inputs that heat, then cool, under a load swinging the clamp-side segments past the FORC
    data set's 145 MPa, one after another."""
    f = 130e6 * AREA * (1 + 0.3 * np.sin(np.arange(n) / 60))
    return np.where(np.arange(n) < 300, 6.0, 0.0), f


@pytest.mark.parametrize("params", [
    {}, {"hysteresis": 1.0, "contact_conductance": 2e-3, "composition_shift": 3.0},
    {"drive_current": 1.0, "n_segments": 6.0, "segment_length[2]": 0.01, "mu_f": 0.05}],
    ids=["nominal", "forc-1-heat-loss-shift", "current-six-segments"])
def test_kernel_paths_agree(params):
    """The compiled kernel gives the bits of its plain-Python source along a run through heating,
    cooling and stresses past the data set's (clamped)."""
    from kernel_paths import assert_paths_agree
    u, f = _clamping_run()
    u = u / 12 if params.get("drive_current") else u

    def inputs(k):
        return {"u": u[k], "flange_f": f[k]}
    assert_paths_agree(in_process(CapstanMultiplier, "mult", **params), inputs, 2e-3, len(u))


def test_each_segments_first_stress_clamp_is_logged_once_in_time_order():
    # segment 1 (the highest tension) leaves the FORC data set's 105-145 MPa at the start, the
    # others later as the load swings up; each is warned of once, at its first clamp (the start,
    # before initialization, and initialization each start a new fold, as the FMU always did)
    slave = in_process(CapstanMultiplier, "mult", hysteresis=1.0)
    u, f = _clamping_run()
    r = run_wire(slave, u, f, names=("segment[1]_stress", "flange_s"))
    logged = [m.msg for m in slave.log_queue]
    assert [m.split(" Pa")[0] for m in logged] == [
        "stress of segment 1 1.50874e+08", "stress of segment 1 1.50874e+08",
        "stress of segment 2 1.45634e+08", "stress of segment 3 1.45187e+08"]
    assert "at t = 0.008 s" in logged[2] and "at t = 0.024 s" in logged[3]
    assert all(m.endswith("clamped to 1.45e+08 Pa (warned once)") for m in logged)
    assert r["segment[1]_stress"].max() > 145e6  # the output is the capstan stress, unclamped


def test_a_fused_run_logs_the_clamps_of_the_unfused_run(fmu_dir):
    """The pulse scenario on the FORC data set under a heavier spring: the stress clamps the
    kernel keeps in its state come out of a fused run as the unfused run logs them."""
    from musclesim.cosim import Master, load_scenario
    from musclesim.fmu.compiled import COMPILED

    from conftest import SCENARIOS
    s = load_scenario(SCENARIOS / "sma-multiplier-pulse.toml",
                      ["mult.hysteresis=1", "spring.preload=1.7"], stop_time=0.5)
    fused_master = Master(s, fmu_dir)
    fused = fused_master.run()
    unfused = Master(s, fmu_dir, fuse=False).run()
    assert fused_master.fused == COMPILED
    assert fused.warnings == unfused.warnings
    # segment 1 at the start, 2 and 3 as the contracting wire stretches the spring (in the loop)
    assert [w.split(" ")[4] for w in fused.warnings] == ["1", "2", "3"], fused.warnings
    assert "at t = 0.30275 s" in fused.warnings[1] and "at t = 0.4075 s" in fused.warnings[2]
    assert fused.data.tobytes() == unfused.data.tobytes()
