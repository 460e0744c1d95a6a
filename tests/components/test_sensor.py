"""The scalar-sensor core (components/sensors/sensor.py): lag exact for a ramp, bias and
quantisation, seeded noise."""
import math

import numpy as np
import pytest

from musclesim.components.sensors import sensor as tc


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
