"""A scenario's values and names checked as it loads, before any FMU is read (issue 59): an
implausible value (in the file, its parameters file, ``--set`` or a sweep's grid) is refused naming
where it was written and the value likely meant; an unknown instance is named once, with the
declared name nearest it."""
import pytest

from musclesim.batch import sweep
from musclesim.cosim import ParamRef, implausible, load_scenario, unknown_instance
from musclesim.errors import UserError

from conftest import SCENARIOS

IDEAL = SCENARIOS / "crawler-ideal.toml"
TRACKING = SCENARIOS / "sma-temperature-tracking.toml"
SCENARIO_FILES = sorted(p for p in SCENARIOS.glob("*.toml")
                        if "[sweep]" not in p.read_text())  # the sweep files name a scenario

WIRE = """\
format = 2
step = 0.001
stop_time = 0.01
record = ["wire.T"]
[instances.wire]
component = "SmaWire"
"""


@pytest.mark.parametrize("path", SCENARIO_FILES, ids=lambda p: p.stem)
def test_every_shipped_scenario_and_its_parameter_files_pass(path):
    load_scenario(path)


def test_a_value_in_the_file_is_refused_naming_the_file_and_the_value_likely_meant(tmp_path):
    path = tmp_path / "x.toml"
    path.write_text(WIRE + "parameters = { T_init = 45.0 }\n")
    with pytest.raises(UserError) as err:
        load_scenario(path)
    assert str(err.value) == (
        f"scenario {path} has 1 problem(s): wire.T_init = 45 K is below the plausible 150-1500 K "
        "for a temperature; 45 looks like degrees Celsius: write 318.15 K")
    load_scenario(path, ["wire.T_init=318.15"])  # a --set replaces it, checked itself


def test_a_value_from_a_parameters_file_names_that_file_not_the_value(tmp_path):
    (tmp_path / "params").mkdir()
    (tmp_path / "params" / "w.toml").write_text("T_amb = 21.5\nT_init = 300.0\n")
    path = tmp_path / "x.toml"
    path.write_text(WIRE + 'parameters_file = "params/w.toml"\nparameters = { T_init = 20.0 }\n')
    with pytest.raises(UserError) as err:
        load_scenario(path)
    message = str(err.value)
    assert f"wire.T_amb in {tmp_path / 'params' / 'w.toml'} is below the plausible" in message
    assert "it looks like degrees Celsius: add 273.15 K" in message and "21.5" not in message
    assert "wire.T_init = 20 K" in message  # inline, over the file's: the scenario's own


@pytest.mark.parametrize("setting, message", [
    ("wire.T_init=45", "--set 'wire.T_init=45': wire.T_init = 45 K is below the plausible "
     "150-1500 K for a temperature; 45 looks like degrees Celsius: write 318.15 K"),
    ("wire.T_init=-20", "-20 looks like degrees Celsius: write 253.15 K"),
    ("reference.offset=75", "--set 'reference.offset=75': reference.offset = 75 K is below"),
    ("wire.length=58.42", "58.42 looks like mm: write 0.05842 m"),
])
def test_a_set_value_is_refused_before_any_fmu_is_read(setting, message):
    with pytest.raises(UserError) as err:
        load_scenario(TRACKING, [setting])
    assert message in str(err.value)


def test_a_body_of_absurd_mass_is_refused():
    with pytest.raises(UserError, match=r"body.m1 = 1e-300 kg is below the plausible 1e-07 to "
                                        r"100 kg for a mass$"):
        load_scenario(IDEAL, ["body.m1=1e-300"])
    s = load_scenario(IDEAL)
    assert implausible(s, ParamRef("body", "m1"), 0.25) is None
    assert implausible(s, ParamRef("nobody", "m1"), -1.0) is None  # the name check's to say


def test_a_misspelt_instance_table_is_named_once_with_what_the_file_declares(tmp_path):
    path = tmp_path / "typo.toml"
    text = IDEAL.read_text().replace("[instances.friction2]", "[instances.fricton2]")
    path.write_text(text.replace('parameters_file = "', f'parameters_file = "{SCENARIOS}/'))
    with pytest.raises(UserError) as err:
        load_scenario(path)
    assert str(err.value) == (f"scenario {path} has 1 problem(s): connections, record, plots: "
                              "no instance 'friction2'; the file declares 'fricton2'")
    with pytest.raises(UserError, match=r"--set 'fricton2.mu_s_high=1': no instance 'fricton2'; "
                                        r"the file declares 'friction2'"):
        load_scenario(IDEAL, ["fricton2.mu_s_high=1"])


def test_an_unknown_name_far_from_every_declared_one_lists_them():
    assert unknown_instance("robot", ["body", "inputs"]) == \
        "no instance 'robot' (instances: body, inputs)"
    assert unknown_instance("bdy", ["body"], "x.toml declares") == \
        "no instance 'bdy'; x.toml declares 'body'"


def test_a_sweep_grid_is_checked_whole_before_its_first_case(tmp_path):
    with pytest.raises(UserError) as err:  # FMUs not even looked for: the folder is empty
        sweep.run(IDEAL, ["body.m1=0.1,200", "inputs.f_f=0.5,1"], tmp_path / "out",
                  fmu_dir=tmp_path)
    assert str(err.value) == (f"grid of {IDEAL}: grid axis 'body.m1': body.m1 = 200 kg is above "
                              "the plausible 1e-07 to 100 kg for a mass; 200 looks like g: "
                              "write 0.2 kg")
    assert not (tmp_path / "out").exists()
