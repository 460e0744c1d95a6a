"""The shipped predictions (scenarios/predictions/*.json) in a run's summary.json: present when
the run is the one they were made for, "not applicable" with why otherwise, absent for a
scenario that has none."""
import json

from musclesim.cli import main
from musclesim.cosim import load_scenario
from musclesim.prediction import SUMMARY_KEY, summary_entry

from conftest import SCENARIOS, schema_errors


def test_a_shipped_run_carries_its_predictions(fmu_dir, tmp_path, capsys):
    """The bending actuator, wire A alone (4 s): every metric with its value, interval and the
    study's value; the prediction is the run's own metric (the same bits)."""
    assert main(["run", "bending-one-wire", "--out", str(tmp_path), "--fmus", str(fmu_dir)]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    entry = summary[SUMMARY_KEY]
    assert entry["applies"] and entry["file"] == "scenarios/predictions/fast-actuation.json"
    assert set(entry["outcomes"]) == set(summary["units"])
    for name, o in entry["outcomes"].items():
        assert o["value"] == summary[name] and o["unit"] == summary["units"][name]
        lo, hi = o["interval90"]
        assert lo <= o["value"] <= hi
    assert entry["outcomes"]["tip_to_tip"]["study"] == 400e-6
    assert entry["outcomes"]["tip_min"]["study"] is None
    assert schema_errors("summary", summary) == []
    assert "predictions with 90 % intervals" in capsys.readouterr().out


def test_a_set_fitted_value_makes_them_not_apply(fmu_dir, tmp_path):
    assert main(["run", "bending-one-wire", "--out", str(tmp_path), "--fmus", str(fmu_dir),
                 "--set", "actuator.series_resistance=18", "--stop-time", "2.5"]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    entry = summary[SUMMARY_KEY]
    assert not entry["applies"] and "outcomes" not in entry
    assert "actuator.series_resistance = 18 instead of its default" in entry["why"]
    assert "stop_time 2.5 s instead of 4 s" in entry["why"]
    assert schema_errors("summary", summary) == []


def test_a_parameter_set_to_its_default_value_is_a_change_too():
    """A value the file does not set, given by --set (even the FMU's default): the run is not
    the predictions' any more, and the entry says which parameter."""
    s = load_scenario(SCENARIOS / "quadruped-walk.toml", ["body.body_mass=0.005"])
    entry = summary_entry(s)[SUMMARY_KEY]
    assert not entry["applies"] and "body.body_mass = 0.005 instead of its default" in entry["why"]


def test_a_scenario_without_predictions_has_no_entry():
    assert summary_entry(load_scenario(SCENARIOS / "crawler-ideal.toml")) == {}
