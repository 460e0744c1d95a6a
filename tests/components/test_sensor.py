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


def test_the_kernels_generator_draws_numpys_stream():
    # the noise's generator lives in the kernel's state: numpy's default_rng(seed) to the bit,
    # the ziggurat's rare branches (wedges, tail beyond 3.65) among 200000 draws
    p = tc.SensorParams(noise_std=1.0, seed=11)
    x = tc.start_state(p)
    n = 200000 if getattr(tc.standard_normal, "py_func", None) is not None else 20000
    drawn = np.array([x[tc.NOISE]] + [tc.standard_normal(x, tc.RNG) for _ in range(n)])
    expected = np.random.default_rng(11).standard_normal(n + 1)
    assert drawn.tobytes() == expected.tobytes()
    assert np.abs(expected).max() > 3.7 or n < 200000  # the tail was drawn
    # the state after them is numpy's too: the next draw agrees
    assert tc.standard_normal(x, tc.RNG) == np.random.default_rng(11).standard_normal(n + 2)[-1]


def test_the_kernel_compiled_and_as_python_agree_to_the_bit():
    if getattr(tc.advance, "py_func", None) is None:
        pytest.skip("numba is not installed: the kernel runs as Python only")
    p = tc.SensorParams(tau=0.02, gain=1.01, origin=273.15, bias=-0.5, noise_std=0.2,
                        quantum=0.05, seed=3)
    kp = tc.pack(p)
    xa, xb, ya, yb = tc.start_state(p), tc.start_state(p), np.zeros(1), np.zeros(1)
    for k in range(500):
        u = np.array([300.0 + 5 * math.sin(k / 30)])
        tc.evaluate(kp, xa, u, k * 1e-3, ya)
        tc.evaluate.py_func(kp, xb, u, k * 1e-3, yb)
        tc.advance(kp, xa, u, ya, k * 1e-3, 1e-3)
        with np.errstate(over="ignore"):  # numpy's uint64 scalars warn where PCG64 wraps
            tc.advance.py_func(kp, xb, u, yb, k * 1e-3, 1e-3)
        assert ya.tobytes() == yb.tobytes() and xa.tobytes() == xb.tobytes()
    assert tc.read(2.5, 1.0, 0.0, 0.0, 1.0, 0.0) == 2.0 == tc.read.py_func(2.5, 1.0, 0.0, 0.0,
                                                                         1.0, 0.0)  # half even
