"""The fast-actuation scenarios of §multiplier-experiments, shortened (the metric ops they report
with: tests/cosim/test_results.py).

Topologies::

    bands:     reference --r--> pid_m --u [A]--> mult --segment[2].T--> tc_m --> pid_m (y)
               weight_m <--flange.s/flange.f--> mult       (and the same chain for the 56 mm wire)
    bang-bang: tc --T--> relay --u [V]--> wire --T--> tc;  weight <--> wire   (two chains)
    pulse:     pulses --u [V]--> mult <--flange.s/flange.f--> spring
"""
import math

import numpy as np
import pytest

from musclesim.cosim import Signal, compute_metrics, master, scenario
from musclesim.errors import UserError

from conftest import SCENARIOS

S = Signal.parse

NEW = ["sma-multiplier-bands", "sma-multiplier-band-50-100", "sma-multiplier-band-60-90",
       "sma-multiplier-bang-bang", "sma-multiplier-pulse", "sma-drift"]


def run(name, fmu_dir, stop_time, overrides=()):
    s = scenario.load(SCENARIOS / f"{name}.toml", list(overrides), stop_time=stop_time)
    res = master.Master(s, fmu_dir).run()
    assert res.error is None, res.error
    return s, res, compute_metrics(res, s.metrics)


@pytest.mark.parametrize("name", NEW)
def test_scenarios_load_and_name_their_spec(name):
    s = scenario.load(SCENARIOS / f"{name}.toml")
    assert s.reference.startswith("§") and s.metrics


def test_a_periodic_op_without_a_period_is_refused(tmp_path):
    text = (SCENARIOS / "sma-multiplier-pulse.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('op = "cycle_peak_to_peak", period = 0.05,',
                                'op = "cycle_peak_to_peak",', 1))
    with pytest.raises(UserError, match="metric 'mean_p2p' needs"):
        scenario.load(bad)


# --- the scenarios ----------------------------------------------------------------------------

def test_without_friction_the_multiplier_moves_the_length_ratio_times_more(fmu_dir):
    # current drive: a fold without friction and without the tubes' heat loss is the straight
    # wire per unit length, so the ratio of the displacements is the ratio of the lengths,
    # n = 214 / 56 (§capstan-multiplier)
    _, res, m = run("sma-multiplier-band-60-90", fmu_dir, 40.0,
                    ["mult.mu_f=0.0", "mult.contact_conductance=0.0"])
    assert m["ratio"] == pytest.approx(0.214 / 0.056, rel=1e-6)
    assert m["ratio"] == pytest.approx(m["multiplier_p2p"] / m["straight_p2p"], rel=1e-12)
    assert m["tracking_rms_multiplier"] < 0.1  # K


def test_with_friction_the_clamp_segments_carry_more_and_move_more(fmu_dir):
    # friction alone, on the reference wire: the tubes' heat loss off (it cools the segments
    # unequally) and no transformation shift (the band then sits on the loop's steep middle)
    _, res, m = run("sma-multiplier-band-60-90", fmu_dir, 40.0, [
        "mult.contact_conductance=0.0", "mult.composition_shift=0.0", "wire.hysteresis_shift=0.0"])
    ratio = math.exp(0.0237 * math.pi)
    np.testing.assert_allclose(res[S("mult.segment[1].stress")], res[S("mult.segment[3].stress")]
                               * ratio ** 2, rtol=1e-14)
    # the minor loop 60-90 C grows with stress (§forc-identification): more than n
    assert m["ratio"] > 0.214 / 0.056 * 1.02
    late = res.time >= 20.0
    assert np.ptp(res[S("mult.segment[1].strain")][late]) > np.ptp(res[S("mult.segment[3].strain")][late])


def test_bang_bang_holds_the_measured_temperature_between_the_thresholds(fmu_dir):
    # ideal thermocouples: the temperature measured is the wire's (the scenario's lag lets the
    # wire overshoot the thresholds by about a kelvin, test_bang_bang_overshoots_by_the_lag)
    _, res, _ = run("sma-multiplier-bang-bang", fmu_dir, 4.0, ["tc_m.tau=0.0", "tc_s.tau=0.0"])
    late = res.time >= 1.0
    for T, on in (("mult.segment[2].T", "relay_m.on"), ("wire.T", "relay_s.on")):
        assert 348.15 - 0.2 < res[S(T)][late].min() and res[S(T)][late].max() < 363.15 + 0.2
        switches = np.flatnonzero(np.diff(res[S(on)][late]) > 0)
        assert len(switches) >= 4  # the relay oscillates
        # every switch-on follows a fall to 75 C, every switch-off a rise to 90 C
        assert np.all(res[S(T)][late][switches + 1] <= 348.15)
    # the displacement's frequency is the relay's
    on_times = res.time[late][np.flatnonzero(np.diff(res[S("relay_s.on")][late]) > 0) + 1]
    f = compute_metrics(res, {"f": scenario.Metric(S("wire.flange.s"), "frequency", start=1.0)})["f"]
    assert f == pytest.approx(
        (len(on_times) - 1) / (on_times[-1] - on_times[0]), rel=0.05)


def test_bang_bang_overshoots_by_the_lag(fmu_dir):
    # the thermocouples' fitted lag (§study-outcomes): the relay switches off once the reading
    # reaches 90 C, when the wire is hotter by about the heating rate times the lag
    _, res, _ = run("sma-multiplier-bang-bang", fmu_dir, 4.0)
    late = res.time >= 1.0
    T = res[S("wire.T")][late]
    rate = np.max(np.diff(T)) / 4e-4  # K/s while heating
    over = T.max() - 363.15
    assert 0.3 * rate * 0.006 < over < 2.0 * rate * 0.006


def test_pulses_are_7_5_ms_of_13_125_V_every_50_ms(fmu_dir):
    s, res, m = run("sma-multiplier-pulse", fmu_dir, 1.0)
    u = res[S("pulses.y")][:-1]  # held over each step
    per_period = u.reshape(-1, round(0.05 / s.step))
    # high over steps 1..30 of each period (the wave is delayed by half a step)
    assert np.all(per_period[:, 1:31] == 13.125)
    assert np.all(per_period[:, 31:] == 0.0) and np.all(per_period[:, 0] == 0.0)
    assert res[S("mult.flange.s")][-1] > 0.005  # the first pulses contract it against the spring
    assert res[S("spring.flange.f")][-1] == pytest.approx(
        1.5834609 + 490.0 * res[S("mult.flange.s")][-1], rel=1e-6)
