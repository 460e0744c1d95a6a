"""Regime masks on synthetic signals (no FMU): which column defines which regime, heating,
cooling and hot on a temperature ramp, switching windows after indicator changes, the gap per
regime."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from musclesim.cosim import Signal
from musclesim.diagnosis import effects
from musclesim.diagnosis.regimes import (Signals, regime_signals, regime_table, regimes,
                                         run_masks)

T = np.round(np.arange(0, 10.0001, 0.01), 10)  # 1001 samples at 100 Hz


def test_heating_cooling_and_hot_on_a_temperature_ramp():
    temp = 300 + 20 * np.minimum(T, 10 - T)  # up to 400 K at 5 s, back down
    masks = run_masks(T, {"w.T": temp}, Signals(temperature="w.T"))
    assert set(masks) == {"all", "late", "changing", "heating", "cooling", "hot"}
    assert masks["heating"][T < 4.9].all() and not masks["heating"][T > 5.1].any()
    assert masks["cooling"][T > 5.1].all() and not masks["cooling"][T < 4.9].any()
    hot = masks["hot"]  # the top fifth of the temperatures: within 1 s of the peak
    assert hot[(T > 4.05) & (T < 5.95)].all() and not hot[(T < 3.95) | (T > 6.05)].any()
    assert masks["late"].sum() == (T >= 5).sum() and masks["all"].all()


def test_switching_is_the_half_second_after_an_indicator_changes():
    u1 = np.where((T >= 2) & (T < 6), 1.0, 0.0)  # switches on at 2 s, off at 6 s
    u2 = np.where(T >= 8.2, 1.0, 0.0)
    masks = run_masks(T, {"inputs.u1": u1, "inputs.u2": u2},
                      Signals(indicators=("inputs.u1", "inputs.u2")))
    expected = ((T >= 2) & (T < 2.5)) | ((T >= 6) & (T < 6.5)) | ((T >= 8.2) & (T < 8.7))
    assert np.array_equal(masks["switching"], expected)


def test_force_pressure_strain_and_positions():
    f = 5 + np.sin(2 * np.pi * 0.5 * T)
    strain = np.where(T < 5, 0.0, 0.04 * np.clip(T - 5, 0, 1))  # transforms during 5..6 s
    x = np.where(T < 3, 0.0, 0.01 * (T - 3))  # the block slides from 3 s on
    p = 1e5 + 1e4 * np.cos(2 * np.pi * 0.25 * T)
    masks = run_masks(T, {"m.f": f, "w.strain": strain, "b.s": x, "p.p": p},
                      Signals(force="m.f", strain="w.strain", positions=("b.s",),
                              pressure="p.p"))
    assert np.array_equal(masks["high_force"], f > np.median(f))
    assert masks["stress_extremes"].mean() == pytest.approx(0.5, abs=0.02)  # |sin| > 1/sqrt(2)
    assert masks["transformation"][(T > 5.2) & (T < 5.8)].all()
    # (the moving average's zero padding makes a rate in the last 0.125 s: left out)
    assert not masks["transformation"][(T < 4.8) | ((T > 6.2) & (T < 9.8))].any()
    assert masks["slip"][T > 3.1].all() and masks["stick"][T < 2.9].all()
    assert np.array_equal(masks["pressurised"], p > np.median(p))
    changing = masks["pressure_changing"]  # the cosine changes fastest at 1, 3, 5 s, least at 2, 4
    assert changing[(T > 0.8) & (T < 1.2)].all() and changing[(T > 2.8) & (T < 3.2)].all()
    assert not changing[(T > 1.8) & (T < 2.2)].any() and not changing[(T > 3.8) & (T < 4.2)].any()


def test_regime_signals_read_units_and_the_libraries_declarations():
    S = Signal.parse
    outputs = [S(c) for c in ("w.T", "l.f", "w.strain", "b.s", "c.s")]
    inputs = [S(c) for c in ("i.u1", "i.u2", "o.u1", "i.f_a")]
    units = dict(zip(outputs + inputs, ("K", "N", "1", "m", "m", "1", "1", "1", "N")))
    components = {"w": "SmaWire", "l": "LoadCell", "b": "CrawlerBody", "c": "CrawlerBody",
                  "i": "FrictionSwitchingInputs", "o": "SomethingElse"}
    s = regime_signals(outputs, inputs, units, components)
    assert s == Signals(temperature=S("w.T"), force=S("l.f"), strain=S("w.strain"), pressure=None,
                        positions=(S("b.s"), S("c.s")), indicators=(S("i.u1"), S("i.u2")))
    # the declared actuation force stands in for a load when none is measured in N or Pa
    s = regime_signals([], [S("i.f_a")], {S("i.f_a"): "1"}, components)
    assert s.force == S("i.f_a") and s.indicators == ()
    assert effects.SWITCHING_INDICATORS["FrictionSwitchingInputs"] == ("u1", "u2")


def test_regimes_of_a_problem_keep_what_every_run_defines():
    temp = 300 + 20 * np.minimum(T, 10 - T)
    wire_T = Signal("w", "T")
    ds = SimpleNamespace(outputs=(wire_T,), inputs=(), experiment=lambda name: (T, {wire_T: temp}))
    problem = SimpleNamespace(ds=ds, scalar_only=False, units_of={wire_T: "K"},
                              components={"w": "SmaWire"})
    unit = SimpleNamespace(runs=[SimpleNamespace(time=T, experiment="a"),
                                 SimpleNamespace(time=T, experiment="b")])
    masks = regimes(problem, unit)
    assert list(masks) == [k for k in effects.REGIMES
                           if k in ("all", "late", "changing", "heating", "cooling", "hot")]
    assert all(len(v) == 2 for v in masks.values())
    scalar = regimes(SimpleNamespace(scalar_only=True, ds=ds), unit)
    assert list(scalar) == ["all"] and scalar["all"][0].tolist() == [True]


def test_regime_table_splits_the_gap():
    unit = SimpleNamespace(observed=("a.y",), runs=[SimpleNamespace(time=None)])
    res = {"a.y": [np.array([0.0, 0.0, 0.3, 0.4])]}
    masks = {"all": [np.ones(4, bool)], "late": [np.array([False, False, True, True])],
             "hot": [np.zeros(4, bool)]}
    table = regime_table(unit, res, masks)
    assert table["worst_windows"] == []
    by = table["by_regime"]
    assert by["late"]["fraction"] == 0.5 and by["late"]["gap"] == pytest.approx(math.sqrt(0.125))
    assert by["all"]["gap"] == pytest.approx(math.sqrt(0.25 / 4))
    assert by["hot"]["gap"] is None and by["hot"]["description"] == effects.REGIMES["hot"]
