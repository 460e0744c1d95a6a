"""The scenario commands' arguments (musclesim.cli.scenarios): build, run, export, sweep, each
parsed with its defaults and handler (their runs: test_cli.py and test_bad_inputs.py)."""
import argparse

import pytest

from musclesim.cli import main, scenarios


def parse(add, *argv):
    """`argv` parsed by a parser holding only the command `add` registers."""
    p = argparse.ArgumentParser(prog="musclesim")
    add(p.add_subparsers(dest="command", required=True))
    return p.parse_args([str(a) for a in argv])


def test_build_defaults_to_fmi_2_and_leaves_the_folder_to_main(capsys):
    parsed = parse(scenarios.add_build, "build")
    assert (parsed.fmi, parsed.fmus) == (2, None)  # main picks fmus or fmus3 by version
    assert parse(scenarios.add_build, "build", "--fmi", "3", "--fmus", "f").fmi == 3
    with pytest.raises(SystemExit):
        parse(scenarios.add_build, "build", "--fmi", "1")
    assert "invalid choice: 1" in capsys.readouterr().err


def test_run_needs_an_output_folder_and_hosts_directly_by_default(capsys):
    parsed = parse(scenarios.add_run, "run", "s.toml", "--out", "o")
    assert (parsed.scenario, parsed.out, parsed.host, parsed.set) == ("s.toml", "o", "direct", [])
    assert parse(scenarios.add_run, "run", "s.toml", "--out", "o", "--host", "fmpy").host == "fmpy"
    with pytest.raises(SystemExit):
        parse(scenarios.add_run, "run", "s.toml")
    assert "the following arguments are required: --out" in capsys.readouterr().err


def test_export_writes_either_an_ssp_or_one_fmu(capsys):
    parsed = parse(scenarios.add_export, "export", "s.toml", "--ssp", "a.ssp")
    assert (parsed.ssp, parsed.fmu, parsed.fmi) == ("a.ssp", None, 2)
    with pytest.raises(SystemExit):
        parse(scenarios.add_export, "export", "s.toml", "--ssp", "a.ssp", "--fmu", "b.fmu")
    assert "not allowed with argument" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        parse(scenarios.add_export, "export", "s.toml")
    assert "one of the arguments --ssp --fmu is required" in capsys.readouterr().err


def test_sweep_collects_its_grid_axes():
    parsed = parse(scenarios.add_sweep, "sweep", "s.toml", "--out", "o", "--grid", "a.b=0:1:3",
                   "--grid", "c.d=1:2:2", "--workers", "2")
    assert (parsed.grid, parsed.workers, parsed.scheduler) == (["a.b=0:1:3", "c.d=1:2:2"], 2,
                                                               None)


def test_build_picks_its_folder_by_fmi_version(monkeypatch, capsys):
    """main gives build the folder of its FMI version when --fmus is not given."""
    seen = []
    monkeypatch.setattr("musclesim.cosim.build_all", lambda fmus, fmi: seen.append((fmus, fmi))
                        or [])
    monkeypatch.setattr("musclesim.cli._check_outputs", lambda args: None)
    assert main(["build", "--fmi", "3"]) == 0 and main(["build"]) == 0
    assert seen == [("fmus3", 3), ("fmus", 2)]


def test_main_runs_a_shipped_scenario_by_name(monkeypatch, tmp_path, capsys):
    """`musclesim run NAME`: a name that is no file is the shipped scenario of that name; an
    unknown one ends in one sentence naming the nearest (exit status 2, before any work)."""
    from conftest import SCENARIOS

    class Ran(Exception):
        """The run started (the run itself is not this test's)."""

    def run_scenario(path, *args, **kwargs):
        seen.append(path)
        raise Ran

    seen = []
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr("musclesim.cosim.run_scenario", run_scenario)
    with pytest.raises(Ran):
        main(["run", "crawler-ideal", "--out", "o"])
    assert seen == [str(SCENARIOS / "crawler-ideal.toml")]
    assert main(["run", "crawler-idael", "--out", "o"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("musclesim: scenario crawler-idael is neither a file nor the name of a "
                          "shipped scenario; the nearest shipped ones are crawler-ideal")
    assert err.count("\n") == 1 and seen == [str(SCENARIOS / "crawler-ideal.toml")]
