"""The calibration parameters of a unit on a hand-made unit (no FMU): one `Free` per component and
parameter shared by its instances, a stated or connected value fixed, too few training values
calibrate nothing; a parameter's nominal value read in one place; the report's table."""
from types import SimpleNamespace

import numpy as np
import pytest

from musclesim.cosim import Instance, ParamRef, Scenario, Signal
from musclesim.diagnosis.fitting import FitResult, Free
from musclesim.diagnosis.parameters import (calibration, calibration_table, nominal, scanned,
                                           unit_of)
from musclesim.diagnosis.thresholds import MIN_VALUES_PER_PARAMETER

OBSERVED = (Signal("tc1", "T_meas"), Signal("tc2", "T_meas"))


def scenario(gains):
    """Two thermocouples, no connection; `gains` {instance: gain} stated in the scenario."""
    return Scenario("bench", None, {n: Instance(n, "Thermocouple", (
        {"gain": gains[n]} if n in gains else {})) for n in ("tc1", "tc2")}, (), 0.1, 1.0)


def problem_unit(gains, rows=40, conditions=(), start="1.0"):
    """(problem, unit) of one run of `rows` training rows, both channels observed; the FMU's
    start value of ``gain`` is `start`."""
    s = scenario(gains)
    run = SimpleNamespace(scenario=s, inputs={}, part=np.zeros(rows, np.int8),
                          time=0.1 * np.arange(rows))
    unit = SimpleNamespace(runs=[run], observed=OBSERVED, instances=("tc1", "tc2"),
                           components={"tc1": "Thermocouple", "tc2": "Thermocouple"})
    var = SimpleNamespace(start=start)
    stated = dict.fromkeys(conditions, 1.0)  # the data set's stated values
    problem = SimpleNamespace(ds=SimpleNamespace(values=lambda experiment=None: stated,
                                                 path="set"),
                              scenarios={"first": s}, fmu_dir="fmus",
                              vars={"tc1": {"gain": var}, "tc2": {"gain": var}})
    return problem, unit


def test_the_nominal_value_is_the_scenarios_else_the_fmus_start():
    problem, _ = problem_unit({"tc1": 1.002})
    assert nominal(problem, ParamRef("tc1", "gain")) == 1.002
    assert nominal(problem, ParamRef("tc2", "gain")) == 1.0  # the FMU's start, a string in FMPy
    problem.vars["tc2"]["gain"] = SimpleNamespace(start=None)
    with pytest.raises(KeyError, match="Thermocouple has no parameter 'gain'"):
        nominal(problem, ParamRef("tc2", "gain"))


def test_one_free_parameter_per_component_and_name_for_all_its_instances():
    problem, unit = problem_unit({"tc1": 1.002})
    free, = calibration(problem, unit)
    # the first instance's nominal value, the declared relative bounds around it
    assert free.instances == ("tc1", "tc2") and free.name == "gain" and free.start == 1.002
    assert (free.lower, free.upper) == pytest.approx((0.9925 * 1.002, 1.0075 * 1.002))
    assert scanned([free]) == 0 and scanned([Free(("pwm",), "phase", 0, 1, 0, 1.0), free]) == 1


def test_a_stated_value_is_fixed_and_too_few_values_calibrate_nothing():
    problem, unit = problem_unit({}, conditions=[ParamRef("tc2", "gain")])
    free, = calibration(problem, unit)
    assert free.instances == ("tc1",)
    problem, unit = problem_unit({}, conditions=[ParamRef("tc1", "gain"), ParamRef("tc2", "gain")])
    assert calibration(problem, unit) == []
    # two observed channels: a parameter needs MIN_VALUES_PER_PARAMETER training values
    enough = MIN_VALUES_PER_PARAMETER // 2
    assert len(calibration(*problem_unit({}, rows=enough))) == 1
    assert calibration(*problem_unit({}, rows=enough - 1)) == []
    assert calibration(*problem_unit({}), instances=["tc2"])[0].instances == ("tc2",)


def test_the_report_table_keys_a_shared_parameter_by_all_its_instances():
    free = [Free(("tc1", "tc2"), "gain", 0.99, 1.01, 1.0)]
    f = FitResult([1.004], [(1.001, 1.007)], None, 0.0, 0.0, True, 1, None, {})
    assert calibration_table(free, f, {"tc1": "Thermocouple"}) == {"tc1,tc2.gain": {
        "value": 1.004, "interval": [1.001, 1.007], "nominal": 1.0, "lower": 0.99,
        "upper": 1.01, "unit": "1"}}


def test_a_parameters_unit_is_its_components_declaration():
    assert unit_of("SmaWire", "T_amb") == "K" and unit_of("SmaWire", "h") == "W/(m2.K)"
    assert unit_of("Thermocouple", "tau") == "s" and unit_of("Thermocouple", "gain") == "1"
    assert unit_of("NotInTheCatalogue", "k") == "1" and unit_of("SmaWire", "nothing") == "1"
    free = [Free(("wire",), "T_amb", 285.15, 301.15, 293.15)]
    f = FitResult([290.0], [(289.0, 291.0)], None, 0.0, 0.0, True, 1, None, {})
    assert calibration_table(free, f, {"wire": "SmaWire"})["wire.T_amb"]["unit"] == "K"
