"""Scoring and ranking the candidates' fits on hand-made numbers (no FMU): a sensor effect
judged on its channel, a failed fit, the ranking with margins."""
import numpy as np
import pytest

from musclesim.diagnosis.scoring import rank, score
from musclesim.diagnosis.stats import gap

from diagnosis_fakes import N, STRAIN, TC, candidate, fake_unit, fitted, noise


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
                                       "upper": 10.0, "off": 0.0, "unit": "K"}
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
