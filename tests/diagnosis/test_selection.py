"""Choosing the effect on hand-made numbers (no FMU): the verdict in each of its cases, what is
explained, the signature, and an effect that does not beat its recalibrated rival."""
from types import SimpleNamespace

import numpy as np
import pytest

from musclesim.diagnosis import effects
from musclesim.diagnosis.fitting import Free
from musclesim.diagnosis.selection import (Candidate, complete, explained, gain_signature, rank,
                                           score, selected_values, signature, verdict)
from musclesim.diagnosis.stats import gap
from musclesim.diagnosis.thresholds import SIGNATURE_MIN

FLOOR = 0.01


def entry(name, before, label=None):
    return {"name": name, "label": label or name, "heldout_gap_before": before}


def test_explained_within_noise_floors_or_a_small_share_of_the_gap():
    assert explained(0.03, 1.0, FLOOR)  # 3 noise floors
    assert not explained(0.031, 0.3, FLOOR)  # above 3 floors and above a tenth of 0.3
    assert explained(0.08, 0.8, FLOOR)  # a tenth of the gap before
    assert not explained(0.081, 0.8, FLOOR)


def test_verdict_none_when_nothing_deviates():
    v, why = verdict([], None, {}, [], FLOOR, deviates=False)
    assert v == "none" and "within the noise" in why


def test_verdict_recalibration_when_a_refitted_parameter_explains_the_gap():
    table = [{"parameters": {"wire.h": 12.5}, "heldout_gap": 0.05},
             {"parameters": {"wire.specific_heat": 900.0}, "heldout_gap": 0.04}]
    v, why = verdict([], None, {0: 0.5}, table, FLOOR)  # the best, 0.04, is a tenth of 0.5
    assert v == "recalibration" and "wire.specific_heat = 900 recalibrated" in why
    v, _ = verdict([], None, {0: 0.15}, table, FLOOR)  # 0.04 > 3 floors and > a tenth of 0.15
    assert v == "unexplained"


def test_verdict_unexplained_without_a_counting_effect():
    v, why = verdict([], None, {0: 0.5}, [], FLOOR)
    assert v == "unexplained" and "no candidate effect" in why


def test_verdict_names_the_effect_complete_or_not():
    lag = entry("thermocouple lag", 0.5)
    final = {"heldout_gap": 0.02}  # within 3 noise floors: complete
    assert verdict([lag], final, {0: 0.5}, [], FLOOR)[0] == "thermocouple lag"
    assert complete([lag], final, FLOOR) is True
    final = {"heldout_gap": 0.2}  # explains 60 %, the rest is structured: named, incomplete
    v, why = verdict([lag], final, {0: 0.5}, [], FLOOR)
    assert v == "thermocouple lag" and "explains 60%" in why and "20.0 noise floors" in why
    assert complete([lag], final, FLOOR) is False
    final = {"heldout_gap": 0.3}  # explains 40 %: less than MOST
    v, why = verdict([lag], final, {0: 0.5}, [], FLOOR)
    assert v == "unexplained" and "thermocouple lag" in why
    assert complete([], None, FLOOR) is False
    pair = [lag, entry("latent heat", 0.4)]
    assert "thermocouple lag + latent heat" in verdict(pair, {"heldout_gap": 0.01}, {0: 0.5}, [],
                                                         FLOOR)[1]


def test_gain_signature():
    gain = np.r_[np.full(10, 1.0), np.full(30, 0.1)]
    regime = np.r_[np.ones(10, bool), np.zeros(30, bool)]
    ratio, ok = gain_signature(gain, regime)
    assert ratio == pytest.approx(1.0 / gain.mean()) and ok
    ratio, ok = gain_signature(gain, ~regime)  # it gains outside the regime it predicts
    assert ratio == pytest.approx(0.1 / gain.mean()) and ratio < SIGNATURE_MIN and not ok
    assert gain_signature(gain, None) == (None, True)
    assert gain_signature(-gain, None)[1] == False  # noqa: E712 (a numpy bool)
    assert gain_signature(-gain, regime) == (None, False)
    assert gain_signature(gain, np.zeros(40, bool)) == (None, False)


def fake_unit(n=200):
    """One run: the first half trains, the second is held out; one observed column."""
    part = np.r_[np.zeros(n // 2, np.int8), np.ones(n // 2, np.int8)]
    return SimpleNamespace(observed=("a.y",), noise={"a.y": FLOOR},
                           runs=[SimpleNamespace(part=part)])


def test_signature_on_synthetic_residuals():
    unit = fake_unit()
    rng = np.random.default_rng(2)
    noise = 0.01 * rng.standard_normal(200)
    hot = np.zeros(200, bool)
    hot[150:170] = True
    before = {"a.y": [noise + np.where(hot, 0.3, 0.0)]}  # the gap is where it is hot
    after = {"a.y": [noise]}
    ratio, ok = signature(unit, before, after, [hot])
    assert ok and ratio == pytest.approx(100 / 20, rel=0.05)  # all the gain on 20 of 100 rows
    cold = ~hot
    ratio, ok = signature(unit, before, after, [cold])
    assert not ok and ratio < 0.1
    assert signature(unit, before, after, None) == (None, True)


def candidate(name="thermocouple bias"):
    e = effects.find(name)
    return Candidate(e, ("thermocouple",), [Free(("thermocouple",), p.name, p.lower, p.upper,
                                                p.off) for p in e.parameters])


def test_an_effect_counts_only_if_it_beats_the_recalibrated_rival():
    unit = fake_unit()
    rng = np.random.default_rng(4)
    noise = 0.01 * rng.standard_normal(200)
    nominal = {"a.y": [noise + 0.2]}
    fitted = {"a.y": [noise + 0.02]}
    f = {"x": [3.0], "interval": [(2.9, 3.1)], "residuals": fitted,
         "heldout_gap": gap(unit, fitted, 1), "applicable": True}
    before = gap(unit, nominal, 1)
    cand = candidate()  # regime "all": consistent when it gains at all
    strong_rival = {0: before, 1: 1.1 * f["heldout_gap"]}  # 0.85 of it is below ours
    e = score(unit, nominal, cand, f, strong_rival, {})
    assert e["shrinkage"] > 0.8 and e["signature"]["consistent"]
    assert not e["beats_recalibrated"] and not e["counts"]
    e = score(unit, nominal, cand, f, {0: before, 1: 2 * f["heldout_gap"]}, {})
    assert e["beats_recalibrated"] and e["counts"]
    assert e["recalibrated_gap"] == 2 * f["heldout_gap"]
    assert e["parameters"]["bias"] == {"value": 3.0, "interval": [2.9, 3.1], "lower": -10.0,
                                       "upper": 10.0, "off": 0.0}
    assert e["interval"][0] < e["shrinkage"] < e["interval"][1]
    assert e["per_signal"]["a.y"]["after"] == pytest.approx(f["heldout_gap"])
    weak = dict(f, residuals={"a.y": [noise + 0.15]})  # shrinks the gap by only 25 %
    weak["heldout_gap"] = gap(unit, weak["residuals"], 1)
    assert not score(unit, nominal, cand, weak, {0: before}, {})["counts"]
    failed = dict(f, residuals=None, heldout_gap=float("inf"))
    e = score(unit, nominal, cand, failed, {0: before}, {})
    assert not e["counts"] and e["interval"] == [0.0, 0.0]


def test_rank_puts_counting_effects_first_with_margins():
    unit = fake_unit()
    nominal = {"a.y": [np.full(200, 0.2)]}
    fits = []
    for level in (0.15, 0.01, 0.05):  # 0.15 shrinks too little to count
        res = {"a.y": [np.full(200, level)]}
        fits.append({"x": [1.0], "interval": [(0.5, 1.5)], "residuals": res,
                     "heldout_gap": gap(unit, res, 1), "applicable": True})
    cands = [candidate("thermocouple bias"), candidate("thermocouple lag"),
             candidate("thermocouple bias")]
    entries, counting = rank(unit, nominal, cands, fits, {0: 0.2, 1: 0.2}, {})
    assert [e["heldout_gap_after"] for e in entries] == pytest.approx([0.01, 0.05, 0.15])
    assert [e["counts"] for e in entries] == [True, True, False]
    assert [t[0] for t in counting] == entries[:2]
    assert entries[0]["margin"] == pytest.approx((0.05 - 0.01) / 0.2)
    assert entries[-1]["margin"] is None


def test_selected_values_take_the_joint_refit():
    entries = [{"name": "a", "instances": ["x", "y"], "parameters": {"p": {"value": 1.0}}},
               {"name": "b", "instances": ["z"], "parameters": {"q": {"value": 2.0}}},
               {"name": "c", "instances": ["w"], "parameters": {"r": {"value": 9.0}}}]
    assert selected_values(entries, ["a"]) == {("x", "p"): 1.0, ("y", "p"): 1.0}
    entries[1]["joint_values"] = {"p": 1.5, "q": 2.5}  # b was added to a and both refitted
    assert selected_values(entries, ["a", "b"]) == {("x", "p"): 1.5, ("y", "p"): 1.5,
                                                    ("z", "q"): 2.5}
