"""The joint fit of the study's outcomes (musclesim.diagnosis.openvalues, §study-outcomes): the
joint data set loads against its scenarios, and a value that ends on its bound is reported as a
model-form warning, not as a fitted value. No run here simulates: the warning is tested on
reports built as `calibrate` builds them."""
import json
from contextlib import nullcontext

import pytest

from musclesim import batch
from musclesim.cli import main
from musclesim.cosim import load_scenario
from musclesim.diagnosis import calibration_markdown, dataset
from musclesim.diagnosis.openvalues import ON_BOUND_WARNING, bound_sentence, bound_status

from conftest import SCENARIOS, schema_errors
from dataset_files import SCALAR, problems_of, write_set

JOINT = SCENARIOS / "data" / "study-fast-actuation-joint"
LOOPS = {"loop_30_130": 0.040, "loop_50_100": 0.033, "loop_60_85": 0.021}


# ---- the joint data set -------------------------------------------------------------------------

def test_the_joint_set_loads_against_its_scenarios_and_holds_nothing_out(fmu_dir):
    ds = dataset.load(JOINT, check_model=True, fmu_dir=fmu_dir)
    assert ds.scalar_only and ds.parts() == (tuple(ds.experiments), ())
    assert {e.scenario for e in ds.experiments.values()} == {
        "sma-multiplier-bands", "sma-multiplier-band-50-100", "sma-multiplier-band-60-90",
        "sma-multiplier-bang-bang", "sma-multiplier-pulse", "bending-one-wire",
        "bending-one-wire-b"}
    for e in ds.experiments.values():  # every outcome has its uncertainty and its conditions
        assert e.conditions and all(m.uncertainty == pytest.approx(0.1 * m.value)
                                    for m in e.metrics.values())
    assert {v.why != "" for v in ds.calibrate} == {True}


@pytest.mark.parametrize("name", LOOPS)
def test_the_loops_run_their_band_at_155_MPa(name):
    # the study's loops: 155 MPa on the 127 um wire, the band as its thermocouple reads it
    e = dataset.load(JOINT).experiments[name]
    s = load_scenario(SCENARIOS / f"{e.scenario}.toml",
                      [f"{ref}={v!r}" for ref, v in e.conditions.items()])
    mass = s.instances["weight_s"].parameters["mass"]
    stress = mass * 9.80665 / (3.141592653589793 / 4 * 127e-6 ** 2)
    assert stress == pytest.approx(155e6, rel=1e-3)
    ref = s.instances["reference"].parameters
    low, high = (int(t) for t in name.split("_")[1:])
    assert (ref["offset"] - ref["amplitude"], ref["offset"] + ref["amplitude"]) == \
        pytest.approx((low + 273.15, high + 273.15))
    assert e.metrics["straight_strain_p2p"].value == LOOPS[name]
    assert e.stop_time == 40.0 and s.metrics["straight_strain_p2p"].start == 20.0


def test_only_a_scalar_set_with_open_values_may_hold_nothing_out(tmp_path):
    everything = SCALAR.replace('held_out = ["b"]', "held_out = []")
    fit_all = everything + '[[calibrate]]\nset = ["body.k"]\nbounds = [100.0, 300.0]\n'
    assert dataset.load(write_set(tmp_path / "fit", fit_all, rows=False),
                        scenarios_dir=SCENARIOS).parts() == (("a", "b"), ())
    assert "the held_out part is empty" in problems_of(
        write_set(tmp_path / "diagnose", everything, rows=False))


# ---- a bound hit is a warning -------------------------------------------------------------------

@pytest.mark.parametrize("value, status, bound", [
    (-5.0, "on bound", "lower"), (-4.8, "on bound", "lower"), (-4.79, "fitted", None),
    (10.0, "fitted", None), (14.79, "fitted", None), (14.8, "on bound", "upper"),
    (15.0, "on bound", "upper")], ids=lambda v: str(v))
def test_a_value_within_1_percent_of_its_range_of_a_bound_is_on_it(value, status, bound):
    got = bound_status(value, -5.0, 15.0)  # 1 % of the range: 0.2
    assert (got["status"], got["bound"]) == (status, bound)
    assert got["warning"] == (None if bound is None else ON_BOUND_WARNING)


def report_of(values):
    """A calibration report as `calibrate` builds it, of open values [(value, lower, upper)]."""
    return {"data_set": "set", "reference": "", "evaluations": 12,
            "parts": {"train": ["a"], "held_out": []},
            "open_values": [{"set": [f"x.p{i}"], "value": v, **bound_status(v, lo, hi),
                             "interval95": [lo, hi], "bounds": [lo, hi], "nominal": lo,
                             "unit": "K", "why": "open"}
                            for i, (v, lo, hi) in enumerate(values)],
            "metrics": [{"experiment": "a", "metric": "m", "part": "train", "measured": 1.0,
                         "uncertainty": 0.1, "unit": "m", "nominal": 0.5,
                         "nominal_error": -0.5, "fitted": 0.9, "fitted_error": -0.1}]}


def test_a_value_on_its_bound_is_a_warning_not_a_fit():
    report = report_of([(15.0, -5.0, 15.0), (0.1, 0.0, 0.3)])
    assert schema_errors("calibration", report) == []
    text = calibration_markdown(report)
    assert "| x.p0 | K | on its upper bound (15, a model-form warning, not a fit) |" in text
    assert "| x.p1 | K | 0.1 |" in text and "held out (predicted): none, every outcome" in text
    sentence = bound_sentence(report)
    assert sentence == ("model-form warning: x.p0 = 15 (its upper bound 15) ended on its bound: "
                        "the data push beyond the range, so it is kept for the record, not a "
                        "fitted value.")
    assert text.rstrip().endswith(sentence)
    assert bound_sentence(report_of([(0.1, 0.0, 0.3)])) is None


def test_the_schema_refuses_an_open_value_without_its_status():
    report = report_of([(0.0, 0.0, 1.0)])
    assert schema_errors("calibration", report) == []
    bad = json.loads(json.dumps(report))
    del bad["open_values"][0]["status"]
    bad["open_values"][0]["bound"] = "middle"
    errors = schema_errors("calibration", bad)
    assert any("'status' is a required property" in e for e in errors)
    assert any(e.startswith("open_values/0/bound: 'middle' is not one of") for e in errors)


def test_the_command_ends_with_the_warning(tmp_path, capsys, monkeypatch):
    report = report_of([(0.3, 0.0, 0.3)])
    monkeypatch.setattr(batch, "dask_client", lambda scheduler, workers: nullcontext())
    monkeypatch.setattr(batch, "dask_map", lambda client: batch.serial_map)
    # no fit: the command's end is what is tested, on a report whose value is on its bound
    monkeypatch.setattr("musclesim.diagnosis.load_dataset", lambda *args, **kwargs: None)
    monkeypatch.setattr("musclesim.cosim.check_fresh", lambda fmus: None)
    monkeypatch.setattr("musclesim.diagnosis.calibrate", lambda *args: report)
    assert main(["calibrate", str(JOINT), "--out", str(tmp_path), "--workers", "1"]) == 0
    out = capsys.readouterr().out.rstrip().splitlines()
    assert out[-1] == bound_sentence(report) and "its upper bound 0.3" in out[-1]
    saved = json.loads((tmp_path / "calibration.json").read_text())
    assert saved["open_values"][0]["status"] == "on bound"

