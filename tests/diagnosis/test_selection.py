"""Describing the candidates' fits on hand-made numbers (no FMU): what is explained, the
signature, an effect judged against calibration on the signals it can change, the aliasing by
the calibration, the refit of the best two, the cross-signal sentence."""
import math
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from musclesim.diagnosis import effects
from musclesim.diagnosis.fitting import FitResult, Free
from musclesim.diagnosis.selection import (Candidate, aliasing, cross_signal, explained,
                                           gain_signature, judge, rank, refine, score, signature)
from musclesim.diagnosis.stats import HELD_OUT, gap
from musclesim.diagnosis.thresholds import REFINED, SIGNATURE_MIN

FLOOR = 0.01
N = 400
TC, STRAIN = "thermocouple.T_meas", "wire.strain"


def entry(name, gain=0.6, signals=(TC,), label=None):
    judged = {"gain": gain, "interval": [gain - 0.05, gain + 0.05], "signals": list(signals),
              "before": 0.1, "after": 0.1 * (1 - gain)}
    return {"name": name, "label": label or name, "judged": judged}


def test_explained_within_noise_floors_or_a_small_share_of_the_gap():
    assert explained(0.03, 1.0, FLOOR)  # 3 noise floors
    assert not explained(0.031, 0.3, FLOOR)  # above 3 floors and above a tenth of 0.3
    assert explained(0.08, 0.8, FLOOR)  # a tenth of the gap before
    assert not explained(0.081, 0.8, FLOOR)


def test_aliasing_of_an_effect_by_the_calibration_on_synthetic_sensitivities():
    """A thermocouple's bias changes only its channel; a room warmer by as much moves the wire
    and so both channels, the transformation temperatures shifted with it give the strain back:
    together they make the bias exactly, unless the strain's sensitivity differs."""
    rng = np.random.default_rng(5)
    dstrain = rng.standard_normal(N)  # the strain's sensitivity to the wire's temperature
    tc, strain = np.r_[np.ones(N), np.zeros(N)], np.r_[np.zeros(N), dstrain]
    ambient, shift = tc + strain, -strain
    jac = np.column_stack([tc, ambient, shift, rng.standard_normal(2 * N)])
    names = ["wire.T_amb", "wire.hysteresis_shift", "wire.h"]
    a = aliasing(jac, 1, names)
    assert a["share"] == pytest.approx(1.0) and a["index"] > 1e3
    assert set(a["with"]) == {"wire.T_amb", "wire.hysteresis_shift"}
    # with the room stated (not calibrated) the ambient's column is gone: no stand-in
    b = aliasing(np.delete(jac, 1, axis=1), 1, names[1:])
    assert b["share"] < 0.01 and b["index"] < 1.1
    assert aliasing(None, 1, names) is None and aliasing(jac[:, :1], 1, []) is None
    assert aliasing(np.zeros_like(jac), 1, names) is None  # an effect that changes nothing
    # in a scored fit, a calibration parameter that ended at its bound cannot stand in: left out
    unit = fake_unit((TC,))
    res = {TC: [noise(9)]}
    base = {"residuals": res, "heldout_gap": gap(unit, res, 1)}
    calib = [Free(("wire",), n, 0.0, 1.0, 0.5) for n in ("T_amb", "hysteresis_shift", "h")]
    f = fitted(unit, res, x=[1.0, 0.5, 0.5, 0.5], jac=jac,
               interval=[(0.9, 1.1)] + [(0.4, 0.6)] * 3)
    e = score(unit, base, candidate("thermocouple bias", "thermocouple"), f, {}, calib)
    assert e["aliasing"]["share"] == pytest.approx(1.0)
    f.x[1] = 1.0  # the ambient at its upper bound
    e = score(unit, base, candidate("thermocouple bias", "thermocouple"), f, {}, calib)
    assert e["aliasing"]["share"] < 0.01 and "wire.T_amb" not in e["aliasing"]["with"]


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


def fake_unit(observed=(TC, STRAIN)):
    """One run: the first half trains, the second is held out; the wire feeds the
    thermocouple."""
    part = np.r_[np.zeros(N // 2, np.int8), np.ones(N // 2, np.int8)]
    scenario = SimpleNamespace(instances={"wire": None, "thermocouple": None},
                               connections=(("wire.T", "thermocouple.T"),))
    return SimpleNamespace(observed=observed, noise={c: FLOOR / 3 for c in observed},
                           instances=("thermocouple", "wire"),
                           runs=[SimpleNamespace(part=part, time=0.02 * np.arange(N),
                                                 scenario=scenario)])


def noise(seed):
    return 0.003 * np.random.default_rng(seed).standard_normal(N)


def test_signature_on_synthetic_residuals():
    unit = fake_unit((TC,))
    hot = np.zeros(N, bool)
    hot[300:340] = True
    before = {TC: [noise(2) + np.where(hot, 0.3, 0.0)]}  # the gap is where it is hot
    after = {TC: [noise(2)]}
    ratio, ok = signature(unit, before, after, [hot])
    assert ok and ratio == pytest.approx(200 / 40, rel=0.05)  # all the gain on 40 of 200 rows
    ratio, ok = signature(unit, before, after, [~hot])
    assert not ok and ratio < 0.1
    assert signature(unit, before, after, None) == (None, True)


def test_judge_counts_a_material_significant_gain_only():
    unit = fake_unit((TC,))
    before = {TC: [noise(3) + 0.05 * np.sin(np.arange(N) / 7)]}  # a structured gap
    strong = judge(unit, before, {TC: [noise(4)]}, (TC,), "all", {})
    assert strong["counts"] and strong["material"] and strong["gain"] > 0.8
    assert strong["interval"][0] > 0.8
    weak = judge(unit, before, {TC: [noise(4) + 0.04 * np.sin(np.arange(N) / 7)]}, (TC,), "all",
                 {})
    assert 0 < weak["gain"] < 0.3 and not weak["counts"]  # too small a share
    # within the noise already (2 floors): a fix of what matches is no explanation
    small = {TC: [noise(3) + 0.0065 * np.sin(np.arange(N) / 7)]}
    j = judge(unit, small, {TC: [noise(3)]}, (TC,), "all", {})
    assert not j["material"] and not j["counts"]
    # a gain that is noise: its bootstrap interval straddles zero
    j = judge(unit, {TC: [noise(3) + 0.03]}, {TC: [noise(5) + 0.03]}, (TC,), "all", {})
    assert j["interval"][0] < 0 < j["interval"][1] and not j["counts"]


def candidate(name, instance):
    e = effects.find(name)
    return Candidate(e, (instance,), [Free((instance,), p.name, p.lower, p.upper, p.off)
                                      for p in e.parameters])


def fitted(unit, res, x=3.0, **changed):
    """A `FitResult` of one parameter at `x` with residuals `res` (fields `changed`)."""
    interval = [(x - 0.1, x + 0.1)] if isinstance(x, float) else []
    f = FitResult(x if isinstance(x, list) else [x], interval, res, math.inf,
                  gap(unit, res, HELD_OUT), True, 1, None, {})
    return replace(f, **changed)


def test_a_sensor_effect_is_judged_on_its_channel_not_drowned_by_another_signal():
    """The strain's own mismatch (the bench's hysteresis is not ours) dominates the pooled gap;
    a clear fix of the thermocouple's channel still counts, judged there."""
    unit = fake_unit()
    strain_mismatch = 0.2 * np.sin(np.arange(N) / 11)
    base_res = {TC: [noise(6) + 0.04], STRAIN: [noise(7) + strain_mismatch]}
    base = {"residuals": base_res, "heldout_gap": gap(unit, base_res, 1)}
    res = {TC: [noise(6)], STRAIN: [noise(7) + strain_mismatch]}
    e = score(unit, base, candidate("thermocouple bias", "thermocouple"), fitted(unit, res),
              {})
    assert e["shrinkage"] < 0.05  # pooled, the fix hardly shows ...
    assert e["judged"]["signals"] == [TC] and e["judged"]["gain"] > 0.8 and e["counts"]
    assert e["per_signal"][STRAIN]["after"] == pytest.approx(e["per_signal"][STRAIN]["before"])
    assert e["parameters"]["bias"] == {"value": 3.0, "interval": [2.9, 3.1], "lower": -10.0,
                                       "upper": 10.0, "off": 0.0}
    # the wire's effect acts on both signals and is judged on both
    wire = score(unit, base, candidate("latent heat", "wire"), fitted(unit, res, 1e4), {})
    assert wire["judged"]["signals"] == [TC, STRAIN]
    failed = fitted(unit, res, residuals=None, heldout_gap=float("inf"))
    e = score(unit, base, candidate("thermocouple bias", "thermocouple"), failed, {})
    assert not e["counts"] and e["interval"] == [0.0, 0.0]


def test_rank_puts_counting_effects_first_with_margins():
    unit = fake_unit((TC,))
    base_res = {TC: [noise(8) + 0.2]}
    base = {"residuals": base_res, "heldout_gap": gap(unit, base_res, 1)}
    fits = [fitted(unit, {TC: [noise(8) + level]}) for level in (0.15, 0.01, 0.05)]
    cands = [candidate("thermocouple bias", "thermocouple"),
             candidate("thermocouple lag", "thermocouple"),
             candidate("thermocouple bias", "thermocouple")]
    scored = rank(unit, [base] * 3, cands, fits, {})
    entries = [t.entry for t in scored]
    assert [e["heldout_gap_after"] for e in entries] == pytest.approx([0.01, 0.05, 0.15],
                                                                      abs=0.002)
    assert [e["counts"] for e in entries] == [True, True, False]  # 0.15 shrinks too little
    # each entry with its own candidate and fit
    assert all(t.candidate is cands[i] and t.fit is fits[i]
               for t, i in zip(scored, (1, 2, 0), strict=True))
    assert entries[-1]["margin"] is None


def test_cross_signal_places_the_gap_in_the_sensor_or_in_the_plant():
    unit = fake_unit()
    sensor = {"label": "thermocouple bias", "counts": True,
              "judged": {"signals": [TC]},
              "per_signal": {TC: {"before": 0.04, "after": 0.004},
                             STRAIN: {"before": 0.006, "after": 0.006}}}
    text = cross_signal(unit, [sensor], [sensor])
    assert "depend on the state of wire" in text and "placed in the sensor" in text
    plant = {"label": "latent heat", "counts": True, "judged": {"signals": [TC, STRAIN]},
             "per_signal": {TC: {"before": 0.04, "after": 0.01},
                            STRAIN: {"before": 0.05, "after": 0.01}}}
    assert "placed in wire" in cross_signal(unit, [plant], [plant])
    assert cross_signal(fake_unit((TC,)), [sensor], [sensor]) is None  # one signal: nothing


def test_refine_refits_the_best_two_from_their_values_and_keeps_only_improvements():
    def fit(train, x, applicable=True, residuals=()):
        return FitResult(x, [], residuals, train, math.inf, applicable, 1, None, {})

    first = [fit(0.5, [1.0]), fit(0.2, [2.0]), fit(0.1, [3.0], applicable=False),
             fit(0.3, [4.0]), fit(0.05, [5.0], residuals=None)]  # a failed fit
    cands = [SimpleNamespace(free=[f"effect{i}"]) for i in range(len(first))]
    asked = []

    def pmap(task, jobs):  # a refit improves the second (0.2 -> 0.15), not the fourth
        asked.extend(jobs)
        return [fit({2.0: 0.15, 4.0: 0.35}[job.x0[0]], [job.x0[0] + 0.5]) for job in jobs]

    out = refine("unit", cands, first, ["calib"], {"tc": 1}, "fmus", pmap)
    # the applicable, successful fits with the lowest training cost, from their own values,
    # every Jacobian column fresh (known None) and the calibration's latency held
    assert REFINED == 2 and [job.x0 for job in asked] == [[2.0], [4.0]]
    assert all(job.free == [f"effect{i}", "calib"] and job.known is None
               and job.latency == {"tc": 1} and job.scan == 0 for job, i in zip(asked, (1, 3)))
    assert out[1].train_gap == 0.15 and out[1].x == [2.5]
    assert out[3] is first[3] and out[0] is first[0]
    assert refine("unit", cands, first, [], {}, "fmus", pmap) is first  # nothing calibrated
