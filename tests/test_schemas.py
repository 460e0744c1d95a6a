"""The JSON Schemas of the output files (musclesim/schemas, shown in the docs) hold for what the
tool writes: a run's summary in each of its states, the worked examples' reports, and (in
tests/diagnosis) a fresh diagnosis's report and a blind benchmark's scores."""
import json
from pathlib import Path

import pytest

from musclesim.batch import write_failure
from musclesim.cosim import run_scenario

from conftest import ROOT, SCENARIOS, schema_errors

EXAMPLES = sorted((ROOT / "docs" / "examples").glob("*/report.json"))


def assert_valid(name, document):
    assert schema_errors(name, document) == []


def test_a_runs_summary_in_every_state(fmu_dir, tmp_path):
    out = tmp_path / "run"
    summary, _ = run_scenario(SCENARIOS / "crawler-ideal.toml", out, fmu_dir, stop_time=0.05,
                              with_plot=False)
    assert summary["status"] == "completed"
    assert_valid("summary", json.loads((out / "summary.json").read_text()))
    # completed, with a metric that has no value (null)
    late = tmp_path / "late.toml"
    late.write_text((SCENARIOS / "crawler-ideal.toml").read_text().replace(
        "[metrics]", '[metrics]\nlate = { signal = "body.x_cm", op = "max", from = 5.0 }'))
    run_scenario(late, out, fmu_dir, stop_time=0.05, with_plot=False)
    saved = json.loads((out / "summary.json").read_text())
    assert saved["status"] == "completed" and saved["late"] is None
    assert_valid("summary", saved)
    # stopped by a failure
    run_scenario(SCENARIOS / "crawler-ideal.toml", out, fmu_dir, stop_time=0.1,
                 overrides=["inputs.f_mean=1.7e308", "inputs.f_amp=1e308"], with_plot=False)
    saved = json.loads((out / "summary.json").read_text())
    assert saved["status"] == "stopped"
    assert_valid("summary", saved)
    # a sweep case that could not start
    write_failure(tmp_path / "case", "scenario x cannot be read")
    assert_valid("summary", json.loads((tmp_path / "case" / "summary.json").read_text()))


def test_a_running_summary_and_a_wrong_one(fmu_dir, tmp_path):
    from musclesim.cosim import Master, load_scenario, signal_units
    from musclesim.cosim.results import RunWriter

    s = load_scenario(SCENARIOS / "crawler-ideal.toml")
    m = Master(s, fmu_dir)
    RunWriter(tmp_path, s, m.columns, signal_units(m)).start()
    running = json.loads((tmp_path / "summary.json").read_text())
    assert running["status"] == "running"
    assert_valid("summary", running)
    # the schema bites: a running summary cannot say it completed, a metric is a number or null
    for wrong in ({**running, "completed": True}, {**running, "mean_speed": "fast"}):
        assert schema_errors("summary", wrong)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.parent.name)
def test_the_worked_examples_reports(path):
    report = json.loads(path.read_text())
    assert_valid("report", report)
    broken = {k: v for k, v in report.items() if k != "verdict"}
    assert schema_errors("report", broken)


def test_there_are_worked_examples():
    assert [p.parent.name for p in EXAMPLES] and all(Path(p).is_file() for p in EXAMPLES)
