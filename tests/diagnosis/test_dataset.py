"""Measured data sets (musclesim.diagnosis.dataset): the format loads, and every kind of mistake
is reported, all at once, naming the file and where in it."""
import math

import numpy as np
import pytest

from musclesim.diagnosis import dataset
from musclesim.errors import UserError

from conftest import SCENARIOS

COLUMNS = ["inputs.f_a", "body.x_cm"]
GOOD_MANIFEST = """\
description = "hand-written crawler data"
scenario = "crawler-ideal"
inputs = ["inputs.f_a"]
outputs = ["body.x_cm"]

[units]
"inputs.f_a" = "N"
"body.x_cm" = "m"

[experiments.first]
span = [0.0, 0.5]
[experiments.second]
span = [0.5, 0.9]
metrics.mean_speed = { value = 0.02, unit = "m/s", uncertainty = 0.001 }

[split]
held_out = ["second"]
"""


def good_rows(n=10, dt=0.1):
    """Samples of a made-up run: a sine force and a creeping centre of mass."""
    return [[round(i * dt, 10), math.sin(i), 0.01 * i] for i in range(n)]


def write_set(folder, manifest=GOOD_MANIFEST, header=("time", *COLUMNS), rows=None):
    """Write data.csv (unless `rows` is False) and manifest.toml by hand, not via the simulator."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "manifest.toml").write_text(manifest)
    if rows is not False:
        rows = good_rows() if rows is None else rows
        lines = [",".join(header)] + [",".join(str(v) for v in row) for row in rows]
        (folder / "data.csv").write_text("\n".join(lines) + "\n")
    return folder


def problems_of(folder, **kwargs):
    kwargs.setdefault("scenarios_dir", SCENARIOS)
    with pytest.raises(UserError) as info:
        dataset.load(folder, **kwargs)
    return str(info.value)


def test_good_time_series_set_loads(tmp_path):
    ds = dataset.load(write_set(tmp_path / "set"), scenarios_dir=SCENARIOS)
    assert not ds.scalar_only
    assert ds.columns == tuple(COLUMNS) and ds.inputs == ("inputs.f_a",)
    assert ds.outputs == ("body.x_cm",)
    assert ds.units == {"inputs.f_a": "N", "body.x_cm": "m"}
    assert ds.scenario_path == SCENARIOS / "crawler-ideal.toml"
    np.testing.assert_allclose(ds.time, np.arange(10) * 0.1)
    np.testing.assert_allclose(ds["body.x_cm"], 0.01 * np.arange(10))
    assert ds.parts() == (("first",), ("second",))
    t, cols = ds.experiment("second")
    np.testing.assert_allclose(t, [0.5, 0.6, 0.7, 0.8, 0.9])
    np.testing.assert_allclose(cols["inputs.f_a"], np.sin([5, 6, 7, 8, 9]))
    assert ds.experiments["second"].metrics["mean_speed"] == dataset.MeasuredMetric(
        0.02, "m/s", 0.001)
    with pytest.raises(UserError, match="no experiment 'third'.*first, second"):
        ds.experiment("third")


def test_blocked_time_split_of_a_single_experiment(tmp_path):
    manifest = 'scenario = "x"\ninputs = ["inputs.f_a"]\noutputs = ["body.x_cm"]\n' \
               "[split]\nheld_out_fraction = 0.3\n"
    ds = dataset.load(write_set(tmp_path / "set", manifest))
    assert list(ds.experiments) == ["all"] and ds.experiments["all"].span == (0.0, 0.9)
    train, held = ds.parts()
    assert (train, held) == (("all/train",), ("all/held_out",))
    t_train, _ = ds.experiment("all/train")
    t_held, cols = ds.experiment("all/held_out")
    np.testing.assert_allclose(t_train, np.arange(7) * 0.1)  # cut at 0.63 s
    np.testing.assert_allclose(t_held, [0.7, 0.8, 0.9])
    assert len(cols["body.x_cm"]) == 3


def _replace(old, new):
    return GOOD_MANIFEST.replace(old, new)


def _rows_with(i, j, value):
    rows = good_rows()
    rows[i][j] = value
    return rows


# id -> (manifest, header, rows, expected fragment of the message)
CASES = {
    "malformed-toml": (GOOD_MANIFEST + "oops = \n", None, None,
                       "manifest.toml is not valid TOML"),
    "unknown-key": (GOOD_MANIFEST.replace("description", "descripton"), None, None,
                    "unknown key 'descripton'"),
    "missing-column": (_replace('outputs = ["body.x_cm"]', 'outputs = ["body.x_cm", "body.v"]'),
                       None, None, "column 'body.v' is missing from data.csv"),
    "unknown-column": (None, ("time", *COLUMNS, "body.extra"),
                       [r + [1.0] for r in good_rows()],
                       "data.csv: column 'body.extra' is in neither inputs nor outputs"),
    "duplicated-column": (None, ("time", "inputs.f_a", "body.x_cm", "body.x_cm"),
                          [r + [1.0] for r in good_rows()], "column 4: 'body.x_cm' appears twice"),
    "bad-column-name": (None, ("time", "inputs.f_a", "x_cm"), None,
                        "'x_cm' is not of the form instance.variable"),
    "first-not-time": (None, ("t", *COLUMNS), None, "the first column must be 'time'"),
    "field-count": (None, None, good_rows()[:3] + [[0.3, 1.0]] + good_rows()[4:],
                    "data.csv line 5: 2 fields where the header has 3"),
    "not-a-number": (None, None, _rows_with(2, 1, "abc"),
                     "data.csv line 4, column 'inputs.f_a': 'abc' is not a number"),
    "nan": (None, None, _rows_with(3, 2, "nan"),
            "data.csv line 5, column 'body.x_cm': nan is not finite"),
    "inf": (None, None, _rows_with(3, 1, "inf"),
            "data.csv line 5, column 'inputs.f_a': inf is not finite"),
    "duplicated-time": (None, None, _rows_with(4, 0, 0.3), "data.csv line 6: time repeats"),
    "decreasing-time": (None, None, _rows_with(4, 0, 0.25),
                        "data.csv line 6: time decreases (0.3 then 0.25 s)"),
    "span-outside": (_replace("span = [0.5, 0.9]", "span = [0.5, 2.0]"), None, None,
                     "experiment 'second': span [0.5, 2.0] s is outside the data [0.0, 0.9] s"),
    "span-malformed": (_replace("span = [0.5, 0.9]", "span = [0.9, 0.5]"), None, None,
                       "span [0.9, 0.5] is not [t0, t1] with t0 < t1"),
    "overlap": (_replace("span = [0.5, 0.9]", "span = [0.4, 0.9]"), None, None,
                "experiments 'first' [0.0, 0.5] and 'second' [0.4, 0.9] overlap"),
    "split-unknown": (_replace('held_out = ["second"]', 'held_out = ["third"]'), None, None,
                      "held_out names unknown experiment 'third'"),
    "split-empty": (_replace('held_out = ["second"]', 'held_out = ["first", "second"]'), None,
                    None, "the train part is empty"),
    "split-missing": (GOOD_MANIFEST.split("[split]")[0], None, None, "no [split] table"),
    "fraction-too-big": (_replace('held_out = ["second"]', "held_out_fraction = 0.99"), None,
                         None, "leaves the train part of experiment 'first' with fewer"),
    "bad-uncertainty": (_replace("uncertainty = 0.001", "uncertainty = -1"), None, None,
                        "metric 'mean_speed': uncertainty -1 is not a finite number >= 0"),
    "no-data-but-columns": (None, None, False, "data.csv is missing but manifest.toml lists"),
}


@pytest.mark.parametrize("case", CASES, ids=list(CASES))
def test_each_error_kind_is_reported(tmp_path, case):
    manifest, header, rows, expected = CASES[case]
    folder = write_set(tmp_path / "set", manifest or GOOD_MANIFEST,
                       header or ("time", *COLUMNS), rows)
    message = problems_of(folder)
    assert message.startswith(f"data set {folder} has ")
    assert expected in message


def test_missing_manifest_and_folder(tmp_path):
    (tmp_path / "empty").mkdir()
    assert "manifest.toml is missing" in problems_of(tmp_path / "empty")
    assert "is not a directory" in problems_of(tmp_path / "nowhere")


def test_many_problems_come_together_in_one_message(tmp_path):
    rows = good_rows()
    rows[2][2] = "nan"
    rows[6][0] = 0.45
    manifest = _replace('held_out = ["second"]', 'held_out = ["third"]').replace(
        '"body.x_cm" = "m"', '"body.y" = "m"')
    folder = write_set(tmp_path / "set", manifest, rows=rows)
    message = problems_of(folder)
    expected = ["data.csv line 4, column 'body.x_cm'", "data.csv line 8: time decreases",
                "[units] names 'body.y'", "unknown experiment 'third'"]
    for fragment in expected:
        assert fragment in message
    assert f"has {len(expected)} problem(s)" in message
    assert "\n" not in message


def test_unknown_scenario_is_a_problem_only_against_the_model(tmp_path):
    folder = write_set(tmp_path / "set", _replace('"crawler-ideal"', '"crawler-nowhere"'))
    assert dataset.load(folder, scenarios_dir=SCENARIOS).scenario_path is None
    message = problems_of(folder, check_model=True, fmu_dir=tmp_path)
    assert "scenario 'crawler-nowhere' not found" in message


REAL = SCENARIOS / "data" / "crawler-real"


def test_scalar_only_real_crawler_set_loads():
    ds = dataset.load(REAL)
    assert ds.scalar_only and ds.columns == ()
    assert ds.parts() == (("forward",), ("backward",))
    fwd, bwd = ds.experiments["forward"], ds.experiments["backward"]
    assert fwd.scenario == "crawler-gait-forward"
    assert fwd.metrics["stride_length"].value == 0.028 and fwd.metrics["stride_length"].unit == "m"
    assert fwd.metrics["mean_speed"].value == 0.0089 and fwd.metrics["mean_speed"].unit == "m/s"
    assert bwd.metrics["stride_length"].value == 0.022 and bwd.metrics["mean_speed"].value == 0.007
    with pytest.raises(UserError, match="scalar-only"):
        ds.experiment("forward")


def test_scalar_only_needs_metrics_and_no_time_split(tmp_path):
    manifest = ('scenario = "crawler-ideal"\n[experiments.a]\n[experiments.b]\n'
                'metrics.v = { value = "fast" }\n[split]\nheld_out_fraction = 0.5\n')
    message = problems_of(write_set(tmp_path / "set", manifest, rows=False))
    assert "experiment 'a': no metrics" in message
    assert "metric 'v': needs value = a finite number" in message
    assert "held_out_fraction needs time series" in message


def test_check_model_accepts_a_good_set(tmp_path, fmu_dir):
    manifest = _replace('"crawler-ideal"', f'"{SCENARIOS / "crawler-ideal.toml"}"').replace(
        '[units]\n"inputs.f_a" = "N"\n', "[units]\n")
    ds = dataset.load(write_set(tmp_path / "set", manifest), check_model=True, fmu_dir=fmu_dir)
    assert ds.units == {"inputs.f_a": "N", "body.x_cm": "m"}  # N filled in from the model


def test_check_model_reports_columns_units_and_metrics(tmp_path, fmu_dir):
    manifest = (_replace('inputs = ["inputs.f_a"]', 'inputs = ["inputs.f_a", "body.nothing", '
                                                     '"pump.p"]')
                .replace('"body.x_cm" = "m"', '"body.x_cm" = "mm"')
                .replace("metrics.mean_speed", "metrics.top_speed"))
    header = ("time", *COLUMNS, "body.nothing", "pump.p")
    folder = write_set(tmp_path / "set", manifest, header, [r + [0, 0] for r in good_rows()])
    message = problems_of(folder, check_model=True, fmu_dir=fmu_dir)
    assert "column 'body.nothing': CrawlerBody has no variable 'nothing'" in message
    assert "column 'pump.p': scenario 'crawler-ideal' has no instance 'pump'" in message
    assert "'body.x_cm' is 'mm' but the model's unit is 'm'" in message
    assert "metric 'top_speed' is not a metric of scenario 'crawler-ideal'" in message
    assert "has 4 problem(s)" in message
    # a metric in the wrong unit
    manifest = _replace('unit = "m/s"', 'unit = "m"')
    message = problems_of(write_set(tmp_path / "set2", manifest), check_model=True,
                          fmu_dir=fmu_dir)
    assert "metric 'mean_speed' is in 'm' but the model's is 'm/s'" in message


def test_a_manifest_without_format_2_may_not_name_a_port_format_2_renamed(tmp_path, fmu_dir):
    """A column named as before format 2 (the PID's u, now y; y was its measurement) is refused
    with the new name, against the model or not; with format = 2 the PID's y is its output."""
    header = ("time", "pid.u", "thermocouple.T_meas")
    manifest = ('scenario = "sma-bench-tracking"\ninputs = ["pid.u"]\n'
                'outputs = ["thermocouple.T_meas"]\n[split]\nheld_out_fraction = 0.5\n')
    rows = [[0.1 * i, 0.5, 300.0] for i in range(10)]
    folder = write_set(tmp_path / "old", manifest, header, rows)
    for check in (True, False):
        message = problems_of(folder, check_model=check, fmu_dir=fmu_dir)
        assert message.endswith("has 1 problem(s): data.csv: column 'pid.u': GainScheduledPID's "
                                "u is pid.y since format 2 (the Modelica Standard Library's port "
                                "names): rename the column and write format = 2 in manifest.toml")
    new = write_set(tmp_path / "new", "format = 2\n" + manifest.replace("pid.u", "pid.y"),
                    ("time", "pid.y", "thermocouple.T_meas"), rows)
    ds = dataset.load(new, check_model=True, fmu_dir=fmu_dir, scenarios_dir=SCENARIOS)
    assert ds.format == 2 and ds.inputs == ("pid.y",)
    # a format-2 manifest naming an old port that no longer exists is told its new name too
    folder = write_set(tmp_path / "mixed", "format = 2\n" + manifest, header, rows)
    assert ("column 'pid.u': GainScheduledPID has no variable 'u' (renamed pid.y: rename the "
            "column)" in problems_of(folder, check_model=True, fmu_dir=fmu_dir))
    # what musclesim writes is format 2
    dataset.write(tmp_path / "written", np.arange(10.0), {"pid.y": np.zeros(10),
                  "thermocouple.T_meas": np.full(10, 300.0)}, ["pid.y"],
                  ["thermocouple.T_meas"], "sma-bench-tracking")
    assert dataset.load(tmp_path / "written", scenarios_dir=SCENARIOS).format == 2


def test_cli_dataset_check(fmu_dir, capsys):
    from musclesim import cli

    real = SCENARIOS / "data" / "crawler-real"
    assert cli.main(["dataset", "check", str(real)]) == 0
    assert "OK (scalar-only; experiments forward, backward" in capsys.readouterr().out
    # its model: the pneumatic crawler's gait scenarios, whose metrics it measures
    assert cli.main(["dataset", "check", str(real), "--model", "--fmus", str(fmu_dir)]) == 0
    assert "OK (scalar-only" in capsys.readouterr().out


def test_scalar_only_experiments_may_shorten_the_model_run(tmp_path):
    ds = dataset.load(REAL)
    assert {e.stop_time for e in ds.experiments.values()} == {12.0}
    manifest = ('scenario = "crawler-ideal"\n[experiments.a]\nstop_time = -1\n'
                'metrics.mean_speed = { value = 0.02, unit = "m/s" }\n')
    assert "experiment 'a': stop_time -1 is not a positive number of seconds" in problems_of(
        write_set(tmp_path / "scalar", manifest, rows=False))
    timed = GOOD_MANIFEST.replace("[experiments.first]\n", "[experiments.first]\nstop_time = 3\n")
    assert "stop_time 3 is for scalar-only sets" in problems_of(write_set(tmp_path / "ts", timed))


def test_the_same_data_against_another_model(fmu_dir):
    """--model swaps the experiments' scenarios: the real crawler's data against the ideal
    model, forward and (mirrored) backward; checked against those models' metrics and units."""
    ds = dataset.load(REAL, check_model=True, fmu_dir=fmu_dir, models={
        "*": "crawler-ideal", "backward": "crawler-ideal-backward"})
    assert ds.experiments["forward"].scenario_path == SCENARIOS / "crawler-ideal.toml"
    assert ds.experiments["backward"].scenario_path == SCENARIOS / "crawler-ideal-backward.toml"
    assert ds.experiments["backward"].metrics == dataset.load(REAL).experiments["backward"].metrics
    message = problems_of(REAL, check_model=True, fmu_dir=fmu_dir,
                          models={"sideways": "crawler-ideal", "forward": "no-such-model"})
    assert "model for experiment 'sideways': the data set has no such experiment" in message
    assert "scenario 'no-such-model' not found" in message


def test_bench_conditions_are_stated_in_the_manifest(tmp_path, fmu_dir):
    """Known conditions of the bench (issue 20 item 1): constant values of parameters or of
    inputs nothing feeds; the diagnosis's model runs with them."""
    from musclesim.diagnosis.problem import Problem

    manifest = _replace('[units]', '[conditions]\n"body.k" = 180.0\n"friction1.theta" = 0.1\n\n'
                                   '[units]')
    ds = dataset.load(write_set(tmp_path / "set", manifest), scenarios_dir=SCENARIOS,
                      check_model=True, fmu_dir=fmu_dir)
    assert ds.conditions == {"body.k": 180.0, "friction1.theta": 0.1}
    assert ds.overrides() == ["body.k=180.0", "friction1.theta=0.1"]
    problem = Problem(ds, fmu_dir)
    assert problem.scenarios["first"].instances["body"].parameters["k"] == 180.0
    bad = _replace('[units]', '[conditions]\n"body.k" = "stiff"\nambient = 1.0\n'
                              '"inputs.f_a" = 2.0\n\n[units]')
    message = problems_of(write_set(tmp_path / "bad", bad), check_model=True, fmu_dir=fmu_dir)
    assert "[conditions] 'body.k' must be a finite number" in message
    assert "[conditions] 'ambient' is not of the form" in message
    assert "[conditions] 'inputs.f_a' is also a column of data.csv" in message
    message = problems_of(write_set(tmp_path / "bad2", _replace(
        '[units]', '[conditions]\n"body.nothing" = 1.0\n"body.flange_a.s" = 0.0\n\n[units]')),
        check_model=True, fmu_dir=fmu_dir)
    assert "has no variable 'nothing'" in message
    assert "body.flange_a.s is an output, not a parameter or an input" in message


SCALAR = ('scenario = "crawler-ideal"\n'
          '[experiments.a]\nconditions = { "body.k" = 210.0 }\n'
          'metrics.mean_speed = { value = 0.02, unit = "m/s" }\n'
          '[experiments.b]\nmetrics.mean_speed = { value = 0.03, unit = "m/s" }\n'
          '[conditions]\n"body.c" = 1.2\n[split]\nheld_out = ["b"]\n')


def test_open_values_and_an_experiments_own_conditions_load(tmp_path):
    manifest = SCALAR + ('[[calibrate]]\nset = ["body.k"]\nbounds = [150.0, 250.0]\n'
                         'why = "the actuator\'s stiffness"\n'
                         '[[calibrate]]\nset = ["friction1.mu_k_low", "friction2.mu_k_low"]\n'
                         'bounds = [0.05, 0.2]\n')
    ds = dataset.load(write_set(tmp_path / "set", manifest, rows=False))
    assert ds.calibrate == (
        dataset.OpenValue(("body.k",), 150.0, 250.0, "the actuator's stiffness"),
        dataset.OpenValue(("friction1.mu_k_low", "friction2.mu_k_low"), 0.05, 0.2))
    # the set's conditions, then the experiment's own (which may override them)
    assert ds.overrides("a") == ["body.c=1.2", "body.k=210.0"]
    assert ds.overrides("b") == ds.overrides() == ["body.c=1.2"]


def test_bad_open_values_are_reported(tmp_path):
    manifest = SCALAR + ('[[calibrate]]\nset = ["k"]\nbounds = [1.0, 2.0]\n'
                         '[[calibrate]]\nset = ["body.k"]\nbounds = [2.0, 1.0]\n'
                         '[[calibrate]]\nset = ["body.c"]\nbounds = [1.0, 2.0]\nstep = 1\n'
                         '[[calibrate]]\nset = ["body.c"]\nbounds = [1.0, 3.0]\n')
    manifest = manifest.replace('conditions = { "body.k" = 210.0 }',
                                'conditions = { "body.k" = "stiff" }')
    message = problems_of(write_set(tmp_path / "set", manifest, rows=False))
    assert "[[calibrate]] 1: set must list one or more \"instance.parameter\" names" in message
    assert "[[calibrate]] 2: bounds [2.0, 1.0] is not [lower, upper] with lower < upper" in message
    assert "[[calibrate]] 3: unknown key 'step'" in message
    assert "[[calibrate]]: 'body.c' is in more than one set" in message
    assert "experiment 'a': [conditions] 'body.k' must be a finite number" in message


def test_the_studys_outcomes_load_against_their_scenarios(fmu_dir):
    ds = dataset.load(SCENARIOS / "data" / "study-fast-actuation", check_model=True,
                      fmu_dir=fmu_dir)
    assert ds.scalar_only and ds.parts() == (("bang_bang", "wire_a", "wire_b"), ("pulse",))
    assert {e.scenario for e in ds.experiments.values()} == {
        "sma-multiplier-bang-bang", "sma-multiplier-pulse", "bending-one-wire",
        "bending-one-wire-b"}
    for e in ds.experiments.values():  # every outcome has its uncertainty, and its conditions
        assert e.conditions and all(m.uncertainty == pytest.approx(0.1 * m.value)
                                    for m in e.metrics.values())
