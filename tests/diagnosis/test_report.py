"""The report's files from a `Report` (no FMU): report.json as the schema says, the same
document the object gives, written last; report.md's sections read from the object."""
import json

import pytest

from musclesim.diagnosis.report import markdown, write

from conftest import ROOT, schema_errors
from report_of import report_of
from test_sections import small, without_advice


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
    assert text == json.dumps(report.to_json(), indent=1) + "\n"
    assert without_advice(json.loads(text)) == without_advice(doc)  # no value of it changed
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
    doc = json.loads((folder / "report.json").read_text())
    report = report_of(doc)
    assert markdown(report, ["signals.png", "effects.png"]) == (folder / "report.md").read_text()


def test_report_md_gives_every_value_its_unit_and_flags_those_on_a_bound():
    """The lag example as a diagnosis now writes it (its parameters with their units): the
    calibration's table has a unit column and a bound column, the effect's value its unit, a
    warnings paragraph names the values on their bounds, the verdict's paragraph ends in the
    next step; gaps say they are of unit 1."""
    from test_advice import example

    report = report_of(example("sma-independent-thermocouple-lag"))
    doc, md = report.to_json(), markdown(report)
    assert "| parameter | unit | nominal | calibrated [95 % interval] | bounds | on a bound |" in md
    assert "| wire.T_amb | K | 293.15 | 285.15 [285.15, 301.15] | [285.15, 301.15] | **yes**" in md
    assert "| wire.h | W/(m2.K) | 100 | 91.857 [60, 160] | [60, 160] | no |" in md
    assert "| thermocouple lag | tau = 0.2903 [0.284, 0.297] s |" in md
    assert "**Warnings** (values on a bound of their range):" in md
    for w in doc["warnings"]:
        assert f"- {w}." in md
    verdict = md.split("## Verdict")[1].split("\n\n")[1]
    assert verdict.endswith(f". Next step: {doc['next_step']}.")
    assert "| signal | NRMSE [1] | held-out NRMSE [1] | bias (data - model) | lag [s] |" in md
    assert "-2.26 K" in md  # a bias in its signal's unit
