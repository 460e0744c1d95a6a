"""Signal shapes (components/sources/signals.py): the waves by hand, the square wave's duty."""
import numpy as np
import pytest


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
