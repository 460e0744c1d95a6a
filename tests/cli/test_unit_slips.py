"""The command line on a unit slip, a misspelt instance and an output it cannot write (issue 59):
exit 2 before any work, in one sentence naming the flag or file, the culprit and what to write.
No FMU is read: every refusal here comes before (the FMU folder given is empty)."""
import pytest

from musclesim import cli

from conftest import SCENARIOS

IDEAL = SCENARIOS / "crawler-ideal.toml"
TRACKING = SCENARIOS / "sma-temperature-tracking.toml"


def run(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("command, scenario, setting, sentence", [
    ("run", TRACKING, "wire.T_init=45", "--set 'wire.T_init=45': wire.T_init = 45 K is below the "
     "plausible 150-1500 K for a temperature; 45 looks like degrees Celsius: write 318.15 K"),
    ("run", TRACKING, "reference.offset=75", "75 looks like degrees Celsius: write 348.15 K"),
    ("sweep", IDEAL, "body.m1=1e-300", "body.m1 = 1e-300 kg is below the plausible 1e-07 to 100 "
     "kg for a mass"),
    ("export", IDEAL, "body.m1=200", "200 looks like g: write 0.2 kg"),
])
def test_a_unit_slip_is_refused_before_any_work(command, scenario, setting, sentence, tmp_path,
                                                capsys):
    target = ["--ssp", tmp_path / "x.ssp"] if command == "export" else ["--out", tmp_path / "o"]
    target += ["--grid", "inputs.phi=0:1:2"] if command == "sweep" else []
    code, out, err = run(capsys, command, scenario, *target, "--fmus", tmp_path / "none",
                         "--set", setting)
    assert code == 2 and out == ""
    assert sentence in err and err.count("\n") == 1  # one line
    assert not (tmp_path / "o").exists() and not (tmp_path / "x.ssp").exists()


def test_a_misspelt_instance_table_is_named_once(tmp_path, capsys):
    path = tmp_path / "typo.toml"
    text = IDEAL.read_text().replace("[instances.friction2]", "[instances.fricton2]")
    path.write_text(text.replace('parameters_file = "', f'parameters_file = "{SCENARIOS}/'))
    code, _, err = run(capsys, "run", path, "--out", tmp_path / "o", "--fmus", tmp_path)
    assert code == 2
    assert err == (f"musclesim: scenario {path} has 1 problem(s): connections, record, plots: "
                   "no instance 'friction2'; the file declares 'fricton2'\n")


def test_an_unwritable_output_gives_the_systems_reason_for_the_path_it_failed_on(tmp_path, capsys):
    code, _, err = run(capsys, "run", IDEAL, "--out", "/proc/nope/out", "--fmus", tmp_path)
    assert code == 2
    assert err == ("musclesim: --out /proc/nope/out: cannot create /proc/nope (No such file or "
                   "directory)\n")
