"""`simulate.residuals`: what a sensor channel's acquisition latency may take, on synthetic arrays."""
from dataclasses import replace

import numpy as np
import pytest

from musclesim.diagnosis.problem import Run, Unit
from musclesim.diagnosis.simulate import latency_samples, residuals
from musclesim.diagnosis.stats import HELD_OUT, TRAIN
from musclesim.diagnosis.thresholds import MAX_LATENCY


@pytest.mark.parametrize("rate, late", [(1000.0, 0.03), (50.0, 0.04), (50.0, 0.1)])
def test_a_sensor_channels_latency_is_searched_up_to_a_time_not_a_sample_count(rate, late):
    """A channel nothing reads is compared shifted by the whole number of samples, up to
    MAX_LATENCY, that fits best: 30 ms found at 1 kHz (30 samples), 40 ms at 50 Hz (2 samples),
    and 100 ms at 50 Hz only in part: the search stops at 40 ms."""
    t = np.arange(0.0, 4.0, 1.0 / rate)
    delay = round(late * rate)
    model = np.sin(2 * np.pi * 0.5 * t)
    measured = np.concatenate([np.full(delay, model[0]), model[:-delay]])  # `late` s late
    part = np.where(t < 2.0, TRAIN, HELD_OUT)
    run = Run("one", None, {}, time=t, measured={"cam.s": measured}, part=part)
    unit = Unit("u", ("cam",), ("cam.s",), [run], {"cam.s": 2.0}, {"cam.s": 0.0},
                {"cam": "Camera"}, alignable=("cam.s",))
    shifts = {}
    res = residuals(unit, [{"cam.s": model}], shifts)["cam.s"][0]
    assert latency_samples(unit) == round(MAX_LATENCY * rate)
    assert shifts["cam.s"] == min(delay, latency_samples(unit))
    aligned = np.abs(res[:-delay]).max() < 1e-12
    assert aligned == (late <= MAX_LATENCY)
    # a channel something reads is not shifted
    assert residuals(replace(unit, alignable=()), [{"cam.s": model}], shifts)["cam.s"][0][
        delay] != 0
