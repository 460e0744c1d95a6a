"""The data set's check against the model (musclesim.diagnosis.modelcheck): columns, conditions,
metrics and units against the scenarios and their FMUs, format-1 names, degrees Celsius."""
import numpy as np
import pytest

from musclesim.cosim import ParamRef, Signal
from musclesim.diagnosis import dataset

from dataset_files import COLUMNS, good_rows, problems_of, replace_in_good, write_set

from conftest import SCENARIOS


def test_unknown_scenario_is_a_problem_only_against_the_model(tmp_path):
    folder = write_set(tmp_path / "set", replace_in_good('"crawler-ideal"', '"crawler-nowhere"'))
    assert dataset.load(folder, scenarios_dir=SCENARIOS).scenario_path is None
    message = problems_of(folder, check_model=True, fmu_dir=tmp_path)
    assert "scenario 'crawler-nowhere' not found" in message


def test_check_model_accepts_a_good_set(tmp_path, fmu_dir):
    manifest = replace_in_good('"crawler-ideal"', f'"{SCENARIOS / "crawler-ideal.toml"}"').replace(
        '[units]\n"inputs.f_a" = "N"\n', "[units]\n")
    ds = dataset.load(write_set(tmp_path / "set", manifest), check_model=True, fmu_dir=fmu_dir)
    assert ds.units == {Signal("inputs", "f_a"): "N", Signal("body", "x_cm"): "m"}  # N: the model's


def test_check_model_reports_columns_units_and_metrics(tmp_path, fmu_dir):
    manifest = (replace_in_good('inputs = ["inputs.f_a"]', 'inputs = ["inputs.f_a", "body.nothing", '
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
    manifest = replace_in_good('unit = "m/s"', 'unit = "m"')
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
    assert ds.format == 2 and ds.inputs == (Signal("pid", "y"),)
    # a format-2 manifest naming an old port that no longer exists is told its new name too
    folder = write_set(tmp_path / "mixed", "format = 2\n" + manifest, header, rows)
    assert ("column 'pid.u': GainScheduledPID has no variable 'u' (renamed pid.y: rename the "
            "column)" in problems_of(folder, check_model=True, fmu_dir=fmu_dir))
    # what musclesim writes is format 2
    y, reading = Signal("pid", "y"), Signal("thermocouple", "T_meas")
    dataset.write(tmp_path / "written", np.arange(10.0), {y: np.zeros(10),
                  reading: np.full(10, 300.0)}, [y], [reading], "sma-bench-tracking")
    assert dataset.load(tmp_path / "written", scenarios_dir=SCENARIOS).format == 2


def test_bench_conditions_are_stated_in_the_manifest(tmp_path, fmu_dir):
    """Known conditions of the bench (issue 20 item 1): constant values of parameters or of
    inputs nothing feeds; the diagnosis's model runs with them."""
    from musclesim.diagnosis.problem import Problem

    manifest = replace_in_good('[units]', '[conditions]\n"body.k" = 180.0\n"friction1.theta" = 0.1\n\n'
                                   '[units]')
    ds = dataset.load(write_set(tmp_path / "set", manifest), scenarios_dir=SCENARIOS,
                      check_model=True, fmu_dir=fmu_dir)
    k, theta = ParamRef("body", "k"), ParamRef("friction1", "theta")
    assert ds.conditions == {k: 180.0, theta: 0.1}
    assert list(ds.values().items()) == [(k, 180.0), (theta, 0.1)]
    assert ds.scenario_of("first").instances["body"].parameters["k"] == 180.0
    problem = Problem(ds, fmu_dir)
    assert problem.scenarios["first"].instances["body"].parameters["k"] == 180.0
    bad = replace_in_good('[units]', '[conditions]\n"body.k" = "stiff"\nambient = 1.0\n'
                              '"inputs.f_a" = 2.0\n\n[units]')
    message = problems_of(write_set(tmp_path / "bad", bad), check_model=True, fmu_dir=fmu_dir)
    assert "[conditions] 'body.k' must be a finite number" in message
    assert "[conditions] 'ambient' is not of the form" in message
    assert "[conditions] 'inputs.f_a' is also a column of data.csv" in message
    message = problems_of(write_set(tmp_path / "bad2", replace_in_good(
        '[units]', '[conditions]\n"body.nothing" = 1.0\n"body.flange_a.s" = 0.0\n\n[units]')),
        check_model=True, fmu_dir=fmu_dir)
    assert "has no variable 'nothing'" in message
    assert "body.flange_a.s is an output, not a parameter or an input" in message


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


def test_a_condition_of_an_instance_the_scenario_lacks_is_reported(tmp_path, fmu_dir):
    """with_values skips instances a scenario lacks; the model check says so, by name."""
    manifest = replace_in_good('[units]', '[conditions]\n"pump.p_supply" = 1e5\n\n[units]')
    message = problems_of(write_set(tmp_path / "set", manifest), check_model=True,
                          fmu_dir=fmu_dir)
    assert message.endswith("has 1 problem(s): manifest.toml: [conditions] 'pump.p_supply': "
                            "scenario 'crawler-ideal' has no instance 'pump' (instances: "
                            "inputs, body, friction1, friction2)")


def test_degrees_celsius_in_kelvin_columns_and_conditions_are_refused(tmp_path):
    """A column or a condition in K whose values lie below 200 K is in degrees Celsius (the
    manifest's unit here; the model's without --model when the FMUs are built)."""
    manifest = ('scenario = "sma-bench-stress"\ninputs = ["wire.u"]\noutputs = ["wire.T"]\n'
                '[units]\n"wire.T" = "K"\n[split]\nheld_out_fraction = 0.5\n')
    rows = [[0.1 * i, 0.1, 40.0 + i] for i in range(10)]
    folder = write_set(tmp_path / "set", manifest, ("time", "wire.u", "wire.T"), rows)
    message = problems_of(folder, fmu_dir=tmp_path)  # no FMUs there: the manifest's units
    assert message.endswith("has 1 problem(s): data.csv: column 'wire.T' is in K, but its values "
                            "(40 to 49) are degrees Celsius, not kelvin: add 273.15")
    warm = write_set(tmp_path / "warm", manifest, ("time", "wire.u", "wire.T"),
                     [[r[0], r[1], r[2] + 273.15] for r in rows])
    assert dataset.load(warm, fmu_dir=tmp_path).units[Signal("wire", "T")] == "K"

