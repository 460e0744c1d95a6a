"""Judging an effect's fit on hand-made numbers (no FMU): what is explained, the signature, the
gain judged on the signals an effect can change."""
import numpy as np
import pytest

from musclesim.diagnosis.judging import explained, gain_signature, judge, signature
from musclesim.diagnosis.thresholds import SIGNATURE_MIN

from diagnosis_fakes import FLOOR, N, TC, fake_unit, noise


def test_explained_within_noise_floors_or_a_small_share_of_the_gap():
    assert explained(0.03, 1.0, FLOOR)  # 3 noise floors
    assert not explained(0.031, 0.3, FLOOR)  # above 3 floors and above a tenth of 0.3
    assert explained(0.08, 0.8, FLOOR)  # a tenth of the gap before
    assert not explained(0.081, 0.8, FLOOR)


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
