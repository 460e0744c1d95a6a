"""musclesim.diagnosis.advice: a fitted value on its bound is flagged and named in a warning; every
kind of verdict (none, recalibration, an effect, an effect calibration mimics, a set of several
with and without what separates it, unexplained, incomplete, outside the calibrated family) ends
with its own next step, read from the report's data. Reports made without FMUs (`report_of`,
the docs' worked examples; `small`)."""
import copy
import json
from dataclasses import replace

import pytest

from musclesim.diagnosis.advice import next_step, on_bound, warnings, with_bounds
from musclesim.diagnosis.sections import CalibrationSection, IsolationSection

from conftest import ROOT, schema_errors
from report_of import report_of
from test_sections import small

WHY = "the data push beyond the range; a model-form warning"


def example(name):
    """The worked example `name`'s report.json document, its parameters with their units as a
    diagnosis now writes them (the stored examples may predate them)."""
    doc = json.loads((ROOT / "docs" / "examples" / name / "report.json").read_text())
    units = {"thermocouple.gain": "1", "wire.specific_heat": "J/(kg.K)", "wire.h": "W/(m2.K)",
             "wire.rho_martensite": "Ohm.m", "wire.rho_austenite": "Ohm.m", "wire.T_init": "K",
             "wire.hysteresis_shift": "K", "wire.strain_scale": "1", "wire.T_amb": "K"}
    for k, p in doc["calibration"]["parameters"].items():
        p["unit"] = units[k]
    for e in doc["effects"]:
        for n, p in e["parameters"].items():
            p["unit"] = {"tau": "s", "bias": "K"}.get(n, "1")
    return doc


@pytest.fixture
def lag():
    return example("sma-independent-thermocouple-lag")


@pytest.fixture
def bias():
    return example("sma-independent-thermocouple-bias")


def made(doc):
    """`doc` through the `Report` object, as report.json is written."""
    return report_of(doc).to_json()


def test_a_value_within_one_percent_of_its_range_from_a_bound_is_on_it():
    entry = {"lower": 285.15, "upper": 301.15}  # 16 K: 0.16 K from a bound is on it
    assert on_bound({**entry, "value": 285.15}) and on_bound({**entry, "value": 285.3})
    assert on_bound({**entry, "value": 301.0}) and not on_bound({**entry, "value": 285.4})
    assert not on_bound({"value": 1.0, "lower": 1.0, "upper": 1.0})  # no range
    assert not on_bound({"value": 1.0, "lower": None, "upper": 2.0})
    assert with_bounds({"a": {**entry, "value": 290.0}}) == {
        "a": {**entry, "value": 290.0, "on_bound": False}}


def test_values_on_their_bounds_are_flagged_and_warned_of_in_report_json(lag):
    doc = made(lag)
    params = doc["calibration"]["parameters"]
    flagged = [k for k, p in params.items() if p["on_bound"]]
    assert flagged == ["thermocouple.gain", "wire.T_amb"]  # 0.9925 on 0.9925, 285.15 on 285.15
    assert params["wire.T_amb"]["unit"] == "K" and params["wire.h"]["on_bound"] is False
    assert doc["warnings"] == [
        f"thermocouple.gain = 0.9925 is on its lower bound 0.9925 (within 1 % of its range "
        f"0.9925 to 1.0075): {WHY}",
        f"wire.T_amb = 285.15 K is on its lower bound 285.15 K (within 1 % of its range "
        f"285.15 K to 301.15 K): {WHY}"]
    # an effect's values carry the flag too; a selected effect's on a bound is warned of
    assert [p["on_bound"] for e in doc["effects"] for p in e["parameters"].values()][:2] == [
        False, False]
    pressed = copy.deepcopy(lag)
    pressed["effects"][0]["parameters"]["tau"]["value"] = 1.99
    assert made(pressed)["warnings"][-1].startswith(
        "thermocouple lag: thermocouple.tau = 1.99 s is on its upper bound 2 s")
    assert schema_errors("report", doc) == []


def test_nothing_to_warn_of_when_every_value_sits_inside_its_range():
    doc = small().to_json()
    assert doc["warnings"] == [] and doc["calibration"] == {"parameters": {}}
    assert schema_errors("report", doc) == []


# -- the next step, per kind of verdict -------------------------------------------------------

def test_none_says_to_keep_the_model_and_test_it_elsewhere():
    step = small().to_json()["next_step"]
    assert step.startswith("keep the model as it is (its held-out gap 0.01 of the range is "
                           "within the noise floor 0.02)")


def test_a_recalibration_names_the_values_to_set():
    cal = CalibrationSection(
        {"wire.T_amb": {"value": 289.0, "interval": [288.0, 290.0], "nominal": 293.15,
                        "lower": 285.15, "upper": 301.15, "unit": "K"},
         "wire.h": {"value": 101.0, "interval": [95.0, 105.0], "nominal": 100.0,
                    "lower": 60.0, "upper": 160.0, "unit": "W/(m2.K)"},
         "tc1,tc2.gain": {"value": 1.004, "interval": [1.001, 1.007], "nominal": 1.0,
                          "lower": 0.99, "upper": 1.01, "unit": "1"}},
        {}, 0.05, 0.01, {})
    report = small(IsolationSection([], [], {}), "recalibration")
    doc = replace(report, calibration=cal).to_json()
    # only the values whose interval leaves out their nominal one; a shared one on each instance
    assert doc["next_step"] == ("set the calibrated values in the scenario's parameters "
                                "(`--set wire.T_amb=289 --set tc1.gain=1.004 --set tc2.gain=1.004`)"
                                " and check them on a new recording")
    assert schema_errors("report", doc) == []


def test_an_effect_says_how_to_add_it(lag):
    assert made(lag)["next_step"] == (
        "add thermocouple lag to the model (`--set thermocouple.tau=0.290303` or the "
        "scenario's parameters) and check it on a new recording")


def test_an_effect_calibration_mimics_names_what_breaks_the_symmetry(lag):
    lag["evidence"]["symmetries"] = [{
        "candidates": ["thermocouple lag", "calibration only"], "with": ["wire.h"],
        "breaks_with": ["record rests at a known ambient"], "chi2": 0.5}]
    assert made(lag)["next_step"] == ("to tell thermocouple lag from a recalibration of wire.h, "
                                      "record rests at a known ambient, and diagnose again")


def test_an_incomplete_verdict_says_where_the_gap_left_lies(lag):
    lag["complete"] = False
    assert made(lag)["next_step"].endswith(
        "and check it on a new recording, then look for the further difference the library "
        "does not hold where the gap left is largest (all 42.00-47.98 s)")


def test_a_set_of_several_names_what_separates_it(bias):
    assert made(bias)["next_step"] == (
        "to tell thermocouple bias from calibration only, state wire.T_amb in the data set's "
        "[conditions] (measure it on the bench), and diagnose again")
    bias["evidence"]["symmetries"] = []  # nothing in the report separates them
    assert made(bias)["next_step"] == (
        "record longer, or an experiment that excites thermocouple bias and training drift "
        "differently, and diagnose again")


def test_unexplained_says_where_to_look(lag):
    lag["verdict"] = "unexplained"
    assert made(lag)["next_step"] == (
        "look for a difference the library does not hold where the calibrated gap is largest "
        "(all 42.00-47.98 s), model it, and diagnose again")


def test_outside_the_calibrated_family_the_model_comes_closer_first(lag):
    lag["evidence"]["gate"]["outside"] = True
    assert made(lag)["next_step"] == (
        "bring the model closer to this bench first (where it differs most: thermocouple.gain, "
        "wire.T_amb), then diagnose again: outside the calibrated family the set is only a hint")


def test_each_kind_of_verdict_has_its_own_step(lag, bias):
    kinds = [small().to_json(), made(lag), made(bias)]
    for change in ({"verdict": "unexplained"}, {"complete": False}):
        kinds.append(made({**copy.deepcopy(lag), **change}))
    steps = [next_step(d) for d in kinds]
    assert len(set(steps)) == len(steps) and all(s and "\n" not in s for s in steps)
    assert warnings(kinds[0]) == [] and warnings(kinds[1])  # as their values sit
