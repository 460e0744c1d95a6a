"""The report's files from a `Report` (no FMU): report.json as the schema says, the same
document the object gives, written last; report.md's sections read from the object."""
import json

import pytest

from musclesim.diagnosis.report import markdown, write

from conftest import ROOT, schema_errors
from report_of import report_of
from test_sections import small


@pytest.fixture
def lag():
    doc = json.loads((ROOT / "docs" / "examples" / "sma-independent-thermocouple-lag"
                      / "report.json").read_text())
    return doc, report_of(doc)


def test_report_json_is_the_objects_document(lag, tmp_path):
    doc, report = lag
    (tmp_path / "report.json").write_text("an earlier report")
    paths = write(tmp_path, report)
    assert [p.name for p in paths] == ["report.json", "report.md", "effects.png"]
    text = (tmp_path / "report.json").read_text()
    assert text == json.dumps(doc, indent=1) + "\n"
    assert schema_errors("report", json.loads(text)) == []


def test_report_md_reads_every_section(lag):
    doc, report = lag
    md = markdown(report, ["signals.png"])
    assert md.startswith(f"# Diagnosis of {doc['data_set']}\n")
    assert f"## Verdict: **{doc['verdict']}**" in md and doc["explanation"] + "." in md
    for title in ("## 1. The gap", "## 2. Calibration", "## 3. Where", "## 4. Which cause",
                  "## 5. How far it shrinks"):
        assert title in md
    for key in doc["calibration"]["parameters"]:  # the calibrated values' table
        assert f"| {key} |" in md
    ev = doc["evidence"]
    assert f"Credible set (90% of the probability): **{', '.join(ev['credible'])}**" in md
    assert f"**Calibrated set (95 %): {', '.join(ev['set'])}.**" in md
    assert "Cross-signal evidence: " + doc["consistency"] in md
    assert f"Selected: {', '.join(doc['selected'])}." in md
    assert md.rstrip().endswith("![signals.png](signals.png)")


def test_a_report_without_gap_says_what_did_not_run(tmp_path):
    md = markdown(small())
    assert "## Verdict: **none**" in md and "Nothing calibrated" in md
    assert "No component can be isolated" in md and "No candidate was fitted." in md
    assert "Selected: nothing." in md
    assert [p.name for p in write(tmp_path, small())] == ["report.json", "report.md"]
    assert schema_errors("report", json.loads((tmp_path / "report.json").read_text())) == []


@pytest.mark.parametrize("name", ["sma-independent-thermocouple-lag",
                                  "sma-independent-thermocouple-bias"])
def test_report_md_of_a_worked_example_is_the_one_the_docs_show(name):
    folder = ROOT / "docs" / "examples" / name
    report = report_of(json.loads((folder / "report.json").read_text()))
    assert markdown(report, ["signals.png", "effects.png"]) == (folder / "report.md").read_text()
