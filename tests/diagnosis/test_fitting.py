"""Fitting free parameters on hand-made data (no FMU): a straight line's slope and offset found
by `fit` with intervals that hold them, a failed run a value that says why, the values of shared
parameters, known Jacobian columns, and intervals (test_box)."""
from types import SimpleNamespace

import numpy as np
import pytest

from musclesim.cosim import ParamRef
from musclesim.diagnosis import fitting
from musclesim.diagnosis.fitting import (Free, fit, known_columns,
                                         simulation_task, values_of)
from musclesim.diagnosis.simulate import Failed, Simulated

T = np.linspace(0.0, 1.0, 201)


def line_unit(noise=0.0):
    """A unit of one run observing ``y.out`` = 2 t + 1 (plus `noise`), the first half training,
    the second held out."""
    rng = np.random.default_rng(0)
    part = (T > 0.5).astype(np.int8)
    measured = {"y.out": 2 * T + 1 + noise * rng.standard_normal(T.size)}
    run = SimpleNamespace(part=part, time=T, measured=measured)
    return SimpleNamespace(runs=[run], observed=("y.out",), alignable=(), scale={"y.out": 3.0},
                           noise={"y.out": 0.01})


def line(unit, values, fmu_dir, part=None):
    """`simulate` of the line model a t + b; NaN past the training part with ``part``."""
    y = values[ParamRef("y", "a")] * T + values[ParamRef("y", "b")]
    if part is not None:
        y = np.where(unit.runs[0].part == part, y, np.nan)
    return [{"y.out": y}]


def line_many(unit, sets, fmu_dir, part=None):
    """`simulate_many` of the line model: `line` of each set."""
    return [Simulated(line(unit, values, fmu_dir, part)) for values in sets]


def test_fit_finds_a_lines_slope_and_offset_with_intervals(monkeypatch):
    monkeypatch.setattr(fitting, "simulate", line)
    monkeypatch.setattr(fitting, "simulate_many", line_many)  # a fit here runs its points together
    free = [Free(("y",), "a", 0.0, 5.0, 1.0), Free(("y",), "b", 0.0, 3.0, 2.0)]
    result = fit(line_unit(noise=0.01), free, "fmus")
    assert result.x == pytest.approx([2.0, 1.0], abs=0.02) and result.applicable
    assert all(lo < x < hi for x, (lo, hi) in zip(result.x, result.interval))
    assert result.heldout_gap < 0.01 and result.jac.shape == (101, 2)
    assert set(result.train) == {"y.out"} and result.latency == {}


def test_a_failed_simulation_is_a_value_that_says_why(monkeypatch):
    def failing(unit, values, fmu_dir, part=None):
        raise Failed("the wire's temperature left its table")

    monkeypatch.setattr(fitting, "simulate", failing)
    out = simulation_task((line_unit(), {}, "fmus", None))
    assert out == Simulated(None, "the wire's temperature left its table") and out.failed
    monkeypatch.setattr(fitting, "simulate", line)
    values = {ParamRef("y", "a"): 2.0, ParamRef("y", "b"): 1.0}
    ok = simulation_task((line_unit(), values, "fmus", None))
    assert not ok.failed and ok.error is None
    assert np.array_equal(ok.runs[0]["y.out"], 2 * T + 1)


def test_values_of_shared_parameters_and_their_companions():
    free = [Free(("w1", "w2"), "h", 50.0, 150.0, 100.0, also=(ParamRef("cap", "h_air"),)),
            Free(("tc",), "tau", 0.0, 2.0, 0.0)]
    assert values_of(free, [120.0, 0.3]) == {
        ParamRef("w1", "h"): 120.0, ParamRef("w2", "h"): 120.0, ParamRef("cap", "h_air"): 120.0,
        ParamRef("tc", "tau"): 0.3}
    assert free[0].key == "w1,w2.h" and free[1].refs == (ParamRef("tc", "tau"),)


def test_known_columns_follow_the_effects_parameters():
    jac = np.arange(6.0).reshape(3, 2)
    known = known_columns(jac, 1)
    assert sorted(known) == [1, 2] and np.array_equal(known[2], jac[:, 1])
    assert known_columns(None, 1) is None
