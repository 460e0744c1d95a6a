"""Ideal open-loop actuation (components/crawler/inputs.py, §ideal-actuation): the force's sine and
the indicators' square waves by hand, the mirror direction, parameter errors."""
import math

import pytest

from musclesim.components.crawler.inputs import InputParams, signals

P = InputParams()


def test_force_is_the_sine_around_its_mean_by_hand():
    for t in (0.0, 0.25, 0.5, 0.75, 0.1):
        f_a, _, _ = signals(t, P)
        assert f_a == P.f_mean + P.f_amp * math.sin(2 * math.pi * t)
    assert signals(0.25, P)[0] == pytest.approx(19.9)  # the study's peak
    assert signals(0.75, P)[0] == pytest.approx(0.66)  # and trough


def test_indicators_are_square_waves_with_u2_lagging_by_phi():
    # u1 is high over the first half period; u2 over [phi / 2 pi, phi / 2 pi + 1/2)
    lag = P.phi / (2 * math.pi)
    for t, u1, u2 in ((0.01, 1.0, 0.0), (0.49, 1.0, 1.0), (0.51, 0.0, 1.0),
                      (lag + 0.49, 0.0, 1.0), (lag + 0.51, 0.0, 0.0), (0.99, 0.0, 0.0)):
        assert signals(t, P)[1:] == (u1, u2), t
    # over one period each is high half the time
    n = 10000
    highs = [sum(signals((k + 0.5) / n, P)[i] for k in range(n)) / n for i in (1, 2)]
    assert highs == [pytest.approx(0.5, abs=1e-3)] * 2


def test_direction_minus_one_swaps_the_indicators():
    back = InputParams(direction=-1.0)
    for t in (0.01, 0.3, 0.6, 0.9):
        f_a, u1, u2 = signals(t, P)
        assert signals(t, back) == (f_a, u2, u1)


@pytest.mark.parametrize("params, match", [({"f_f": -1.0}, "f_f must be non-negative"),
                                           ({"f_amp": -0.1}, "f_amp"),
                                           ({"direction": 0.0}, "direction must be 1 or -1")])
def test_bad_parameters_are_named(params, match):
    with pytest.raises(ValueError, match=match):
        InputParams(**params).check()
    P.check()
