"""Training/fatigue drift (components/sma/drift.py, §drift): settled after about 13 tests of 20
cycles, exactly off at no cycles."""
import pytest

from musclesim.components.sma import drift


def test_drift_settles_after_about_13_tests_of_20_cycles():
    d = drift.DriftParams(amplitude_change=-0.1, shift=4.0)
    n = 0.0
    for _ in range(13 * 20):
        n = drift.count_cycles(drift.count_cycles(n, 1.0, 0.0), 0.0, 1.0)
    assert n == 260
    assert drift.progress(n, d) == pytest.approx(0.95, abs=0.01)
    assert drift.strain_scale(n, d) == pytest.approx(1 - 0.095, abs=0.002)
    assert drift.temperature_shift(n, d) == pytest.approx(3.8, abs=0.05)
    assert drift.strain_scale(0.0, d) == 1.0 and drift.temperature_shift(0.0, d) == 0.0
