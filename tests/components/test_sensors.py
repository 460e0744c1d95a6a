"""Thermocouple sensor: exact lag, bias, quantisation, reproducible noise; through its FMU too."""
import math

import numpy as np
import pytest
from fmpy import simulate_fmu

from musclesim.components.sensors import thermocouple as tc


def test_lag_is_exact_for_a_ramp_and_continuous_at_zero():
    # y' = (u - y) / tau with u = r t from y = 0: y = r (t - tau (1 - exp(-t / tau)))
    dt, tau, r, y = 0.02, 0.05, 3.0, 0.0
    a, b = tc.lag_weights(dt, tau)
    for k in range(100):
        y = a * y + (1 - a - b) * r * k * dt + b * r * (k + 1) * dt
    assert y == pytest.approx(r * (2.0 - tau * (1 - math.exp(-2.0 / tau))), rel=1e-12)
    assert tc.lag_weights(dt, 0.0) == (0.0, 1.0)  # no lag: the reading is the signal
    for tiny in (1e-6, 1e-9):  # a lag far below the step is nearly no lag, not a step's delay
        a, b = tc.lag_weights(dt, tiny)
        assert a < 1e-12 and b == pytest.approx(1.0, abs=1e-4)


def test_reading_bias_and_quantisation():
    p = tc.SensorParams(bias=0.5, quantum=0.25)
    assert tc.reading(300.2, p) == 300.75
    assert tc.reading(300.2, tc.SensorParams()) == 300.2
    # a gain scales the signal about the origin: a thermocouple 1 % high reads 101 C at 100 C
    assert tc.reading(373.15, tc.SensorParams(gain=1.01, origin=273.15)) == pytest.approx(374.15)
    assert tc.reading(273.15, tc.SensorParams(gain=1.01, origin=273.15)) == 273.15
    with pytest.raises(ValueError, match="gain"):
        tc.SensorParams(gain=0.0).check()


def test_noise_is_seeded_and_has_the_asked_spread():
    p = tc.SensorParams(noise_std=0.3, seed=4)
    a = [tc.noise_sample(p, r) for r in [tc.make_rng(p)] for _ in range(20000)]
    b = [tc.noise_sample(p, r) for r in [tc.make_rng(p)] for _ in range(20000)]
    assert a == b
    assert np.std(a) == pytest.approx(0.3, rel=0.03) and abs(np.mean(a)) < 0.01


def test_thermocouple_fmu_lags_a_step(fmu_dir):
    r = simulate_fmu(str(fmu_dir / "Thermocouple.fmu"), stop_time=0.2, output_interval=1e-3,
                     start_values={"tau": 0.05, "T": 350.0, "bias": -1.0},
                     output=["T_meas"])
    # the junction starts at the wire's temperature and the input is constant: reading = T + bias
    np.testing.assert_allclose(r["T_meas"], 349.0, rtol=0, atol=1e-9)
    r = simulate_fmu(str(fmu_dir / "Thermocouple.fmu"), stop_time=0.1, output_interval=1e-3,
                     start_values={"T": 373.15, "gain": 1.005}, output=["T_meas"])
    np.testing.assert_allclose(r["T_meas"], 373.65, rtol=0, atol=1e-9)  # 0.5 % of 100 C


@pytest.mark.parametrize("kind, t, expected", [
    (0, 3.0, 2.0), (1, 0.25, 3.0), (2, 0.6, 1.0), (2, 0.1, 3.0), (3, 0.5, 3.0), (3, 0.0, 1.0),
    (4, 0.25, 2.25), (4, 7.0, 3.0),
], ids=["constant", "sine-peak", "square-low", "square-high", "triangle-peak", "triangle-trough",
        "ramp-rising", "ramp-held"])
def test_signal_source_waves(kind, t, expected):
    from musclesim.components.sources import signals

    p = signals.SignalParams(kind=kind, offset=2.0, amplitude=1.0, frequency=1.0)
    assert signals.value(t, p) == pytest.approx(expected, abs=1e-12)
    late = signals.SignalParams(kind=kind, offset=2.0, amplitude=1.0, frequency=1.0, t_start=10.0)
    assert signals.value(t, late) == 2.0  # the offset until the wave starts


def test_square_wave_duty_is_a_pulse_train():
    from musclesim.components.sources import signals

    # 0 / 5 V pulses of 100 ms every 2 s: high for exactly duty x period, average V duty
    p = signals.SignalParams(kind=2, offset=2.5, amplitude=2.5, frequency=0.5, duty=0.05)
    t = np.arange(0, 4, 1e-3)
    y = np.array([signals.value(x, p) for x in t])
    assert set(y) == {0.0, 5.0}
    assert np.count_nonzero(y == 5.0) == 200 and np.mean(y) == pytest.approx(0.25)
    for bad in (0.0, 1.0, 1.2):
        with pytest.raises(ValueError, match="duty must be within"):
            signals.SignalParams(kind=2, duty=bad).check()
