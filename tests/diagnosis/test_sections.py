"""The report as an object: its sections give report.json's document, keys in the order
report.json has always had them, for each way a diagnosis ends (no gap, recalibration, an
effect)."""
import json

import pytest

from musclesim.diagnosis.sections import (CalibrationSection, GapSection, IsolationSection,
                                          Report, ShrinkageSection, VerdictSection)

from conftest import ROOT
from report_of import report_of

EXAMPLES = ("sma-independent-thermocouple-lag", "sma-independent-thermocouple-bias")
HEAD = ["data_set", "scenario", "scalar_only", "parts", "gap", "calibration"]
TAIL = ["shrinkage", "aligned_samples"]


@pytest.mark.parametrize("name", EXAMPLES)
def test_a_worked_examples_report_goes_through_the_object_unchanged(name):
    doc = json.loads((ROOT / "docs" / "examples" / name / "report.json").read_text())
    report = report_of(doc)
    assert json.dumps(report.to_json()) == json.dumps(doc)  # the same keys in the same order
    assert report.effects == doc["effects"] and report.verdict.name == doc["verdict"]
    assert report.calibration.ran


def small(isolation=None, verdict="none"):
    gap = GapSection({"y.x": {"nrmse": 0.01, "nrmse_heldout": 0.01, "bias": 0.0, "unit": "K",
                              "range": 1.0, "noise": 0.002, "lag": 0.0}}, 0.01, 0.02, False)
    shrinkage = {"before": 0.01, "after": 0.01, "interval_before": [0.009, 0.011],
                 "interval_after": [0.009, 0.011], "calibrated": 0.01}
    return Report("set", "bench", False, ["a"], ["b"], gap, CalibrationSection({}), isolation,
                  None, VerdictSection(verdict, "why", True, 0.02, [], []),
                  ShrinkageSection({"y.x": shrinkage, "all": shrinkage}, {}))


def test_a_report_without_gap_or_without_candidates_keeps_its_keys_order():
    none = small()
    assert not none.calibration.ran and none.effects == []
    assert list(none.to_json()) == HEAD + ["effects", "selected", "stand_ins", "verdict",
                                           "explanation", "noise_floor", "complete"] + TAIL
    assert none.to_json()["calibration"] == {"parameters": {}}
    recal = small(IsolationSection([], [], {}), "recalibration")
    assert list(recal.to_json()) == HEAD + ["located", "units", "regimes", "effects",
                                            "selected", "stand_ins", "verdict", "complete",
                                            "noise_floor", "explanation"] + TAIL
    assert recal.to_json()["verdict"] == "recalibration"


def test_sections_are_frozen():
    with pytest.raises(AttributeError):
        small().verdict.name = "other"
