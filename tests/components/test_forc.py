"""The FORC identification experiments' reference (components/sources/forc.py,
§forc-identification): the raised-cosine runs by hand, idle outside them, the cooling bound,
parameter errors."""
import math

import pytest

from musclesim.components.sources.forc import (COOLING, HEATING, IDLE, ForcParams, min_period,
                                               peak, value)

P = ForcParams(T_low=300.0, T_high=320.0, T_step=5.0, period=10.0, t_start=2.0)


def test_runs_one_per_grid_peak():
    assert P.n_runs == 5 and P.duration == 2.0 + 5 * 10.0
    assert [peak(j, P) for j in range(P.n_runs)] == [300.0, 305.0, 310.0, 315.0, 320.0]


def test_each_run_is_a_raised_cosine_to_its_peak_and_back():
    for j in range(P.n_runs):
        start = 2.0 + 10.0 * j
        for x in (0.0, 0.1, 0.25, 0.5, 0.75, 0.9):
            T, run, phase = value(start + 10.0 * x, P)
            hand = 300.0 + (peak(j, P) - 300.0) * (1 - math.cos(2 * math.pi * x)) / 2
            assert T == pytest.approx(hand, abs=1e-12) and run == j
            assert phase == (HEATING if x < 0.5 else COOLING)
        assert value(start + 5.0, P)[0] == pytest.approx(peak(j, P))


def test_outside_the_runs_the_reference_holds_t_low():
    for t in (0.0, 1.999, 52.0, 1e3):
        assert value(t, P) == (300.0, -1.0, IDLE)


def test_min_period_bounds_the_cooling_slope_by_free_cooling():
    """At the bound, the steepest ratio of the reference's fall to free cooling is 1."""
    A, D, tau = 100.0, 10.0, 1.71
    P_min = min_period(A, D, tau)
    xs = [math.pi * k / 2000 for k in range(1, 2000)]
    worst = max(A * math.pi * math.sin(x) / P_min / ((D + A * (1 - math.cos(x)) / 2) / tau)
                for x in xs)
    assert worst == pytest.approx(1.0, rel=1e-12)
    assert min_period(A, 2 * D, tau) < P_min  # a warmer start cools faster


@pytest.mark.parametrize("params, match", [
    ({"T_high": 290.0}, "T_low must be below T_high"), ({"T_step": 0.0}, "T_step"),
    ({"T_step": 3.0}, "whole number of T_step"), ({"period": 0.0}, "period must be positive"),
    ({"t_start": math.nan}, "t_start must be finite")])
def test_bad_parameters_are_named(params, match):
    with pytest.raises(ValueError, match=match):
        ForcParams(**{**P.__dict__, **params}).check()
    P.check()
