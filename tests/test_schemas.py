"""The JSON Schemas of the output files (musclesim/schemas, shown in the docs) hold for what the
tool writes: a run's summary in each of its states, the worked examples' reports, a calibration
written by `musclesim calibrate`, and (in tests/diagnosis) a fresh diagnosis's report and a blind
benchmark's scores."""
import json
from contextlib import nullcontext
from pathlib import Path

import pytest

from musclesim import batch
from musclesim.batch import write_failure
from musclesim.cli import main
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


def test_a_calibration_written_by_musclesim_calibrate(fmu_dir, tmp_path, monkeypatch):
    """A scalar-only set of the stress bench (2 s at two drive levels, the thermocouple's peak
    reading the metric, one level trains and the other is held out) with its thermocouple's
    offset open: the calibration.json `musclesim calibrate` writes holds for its schema, and the
    schema bites on a value outside the pair it must be, a part it does not know, a missing
    section and an unknown key."""
    text = (SCENARIOS / "sma-bench-stress.toml").read_text().replace(
        "stop_time = 60.0", "stop_time = 2.0").replace("from = 10.0", "from = 0.5")
    text = text.replace("[metrics]\n", '[metrics]\nT_max = { signal = "thermocouple.T_meas", '
                        'op = "max" }\n')
    lines = ['reference = "a test of the schema"\n']
    for name, amplitude, reading in (("low", 0.4, 330.0), ("high", 0.5, 340.0)):
        (tmp_path / f"bench-{name}.toml").write_text(
            text.replace("amplitude = 0.5,", f"amplitude = {amplitude},"))
        lines.append(f'[experiments.{name}]\nscenario = "../bench-{name}.toml"\n'
                     f'metrics.T_max = {{ value = {reading}, unit = "K", uncertainty = 0.5 }}\n')
    (tmp_path / "set").mkdir()
    (tmp_path / "set" / "manifest.toml").write_text(
        "".join(lines) + '[split]\nheld_out = ["high"]\n[[calibrate]]\n'
        'set = ["thermocouple.bias"]\nbounds = [-10.0, 10.0]\nwhy = "the reading\'s offset"\n')
    # the fit's runs here, not on a local cluster (whose start alone takes seconds)
    monkeypatch.setattr(batch, "dask_client", lambda scheduler, workers: nullcontext())
    monkeypatch.setattr(batch, "dask_map", lambda client: batch.serial_map)
    assert main(["calibrate", str(tmp_path / "set"), "--out", str(tmp_path / "out"), "--fmus",
                 str(fmu_dir), "--workers", "1"]) == 0
    written = json.loads((tmp_path / "out" / "calibration.json").read_text())
    assert written["open_values"][0]["set"] == ["thermocouple.bias"]
    assert [r["part"] for r in written["metrics"]] == ["train", "held_out"]
    assert_valid("calibration", written)
    value = written["open_values"][0]
    for wrong in ({**written, "open_values": [{**value, "interval95": [0.0]}]},
                  {**written, "metrics": [{**written["metrics"][0], "part": "test"}]},
                  {k: v for k, v in written.items() if k != "parts"},
                  {**written, "verdict": "none"}):
        assert schema_errors("calibration", wrong)

