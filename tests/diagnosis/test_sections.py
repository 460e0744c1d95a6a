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
TAIL = ["shrinkage", "aligned_samples", "warnings", "next_step"]


ADVICE = ("warnings", "next_step")  # what the object adds to a document (sections.py)


def without_advice(doc):
    """report.json document `doc` without what `Report.to_json` derives for its reader: the
    values' ``on_bound``, the ``warnings`` and the ``next_step``."""
    def bare(table):
        return {k: {n: v for n, v in p.items() if n != "on_bound"} for k, p in table.items()}
    out = {k: v for k, v in doc.items() if k not in ADVICE}
    out["calibration"] = {**doc["calibration"], "parameters": bare(doc["calibration"]["parameters"])}
    out["effects"] = [{**e, "parameters": bare(e["parameters"])} for e in doc["effects"]]
    return out


@pytest.mark.parametrize("name", EXAMPLES)
def test_a_worked_examples_report_goes_through_the_object_unchanged(name):
    doc = json.loads((ROOT / "docs" / "examples" / name / "report.json").read_text())
    report = report_of(doc)
    made = report.to_json()
    # the same keys in the same order, every value the same; the reader's advice added after
    assert json.dumps(without_advice(made)) == json.dumps(without_advice(doc))
    assert list(made)[-2:] == list(ADVICE)
    assert json.dumps(report_of(made).to_json()) == json.dumps(made)  # and through it again
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
