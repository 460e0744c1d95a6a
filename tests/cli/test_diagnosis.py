"""The diagnosis's commands (musclesim.cli.diagnosis): dataset check, diagnose, calibrate; their
arguments, and a data set checked (the diagnosis and the calibration run in tests/diagnosis)."""
import argparse

import pytest

from musclesim.cli import diagnosis, main

from conftest import SCENARIOS


def parse(add, *argv):
    """`argv` parsed by a parser holding only the command `add` registers."""
    p = argparse.ArgumentParser(prog="musclesim")
    add(p.add_subparsers(dest="command", required=True))
    return p.parse_args([str(a) for a in argv])


def test_the_diagnosis_commands_arguments(capsys):
    parsed = parse(diagnosis.add_dataset, "dataset", "check", "d", "--model")
    assert (parsed.action, parsed.dataset, parsed.model, parsed.fmus) == ("check", "d", True,
                                                                          "fmus")
    parsed = parse(diagnosis.add_diagnose, "diagnose", "d", "--out", "o", "--model", "m",
                   "--model", "e=n")
    assert (parsed.model, parsed.scheduler, parsed.workers) == (["m", "e=n"], None, None)
    parsed = parse(diagnosis.add_calibrate, "calibrate", "d", "--out", "o", "--workers", "3")
    assert (parsed.dataset, parsed.out, parsed.workers) == ("d", "o", 3)
    with pytest.raises(SystemExit):
        parse(diagnosis.add_dataset, "dataset", "d")
    assert "invalid choice: 'd'" in capsys.readouterr().err


def test_a_model_without_a_scenario_is_refused_before_the_data_set_is_read(tmp_path, capsys):
    assert main(["diagnose", str(tmp_path / "nowhere"), "--out", str(tmp_path / "o"),
                 "--model", "forward="]) == 2
    assert capsys.readouterr().err == ("musclesim: --model 'forward=': give SCENARIO or "
                                       "EXPERIMENT=SCENARIO\n")


def test_cli_dataset_check(fmu_dir, capsys):
    real = SCENARIOS / "data" / "crawler-real"
    assert main(["dataset", "check", str(real)]) == 0
    assert "OK (scalar-only; experiments forward, backward" in capsys.readouterr().out
    # its model: the pneumatic crawler's gait scenarios, whose metrics it measures
    assert main(["dataset", "check", str(real), "--model", "--fmus", str(fmu_dir)]) == 0
    assert "OK (scalar-only" in capsys.readouterr().out
