"""The analysis commands' arguments (musclesim.cli.analysis): table, characterise, linear, each
parsed with its defaults."""
import argparse

import pytest

from musclesim.cli import analysis


def parse(add, *argv):
    """`argv` parsed by a parser holding only the command `add` registers."""
    p = argparse.ArgumentParser(prog="musclesim")
    add(p.add_subparsers(dest="command", required=True))
    return p.parse_args([str(a) for a in argv])


def test_table_runs_the_position_matrix_by_default(capsys):
    parsed = parse(analysis.add_table, "table", "sma-position", "--out", "o", "--only",
                   "stress-aware")
    assert (parsed.scenario, parsed.only, parsed.no_run, parsed.stop_time, parsed.fmus) == (
        "sma-position-control", ["stress-aware"], False, None, "fmus")
    with pytest.raises(SystemExit):
        parse(analysis.add_table, "table", "sma-position", "--out", "o", "--only", "fast")
    assert "invalid choice: 'fast'" in capsys.readouterr().err


def test_characterise_defaults():
    parsed = parse(analysis.add_characterise, "characterise", "--set", "body.k=190")
    assert (parsed.scenario, parsed.out, parsed.write, parsed.set) == (
        "crawler-characterisation", "results/crawler-characterisation", None,
        ["body.k=190"])


def test_linear_knows_five_systems(capsys):
    for system in ("crawler", "sma-thermal", "sma-load", "pneumatic", "bending"):
        assert parse(analysis.add_linear, "linear", system).system == system
    with pytest.raises(SystemExit):
        parse(analysis.add_linear, "linear", "quadruped")
    assert "invalid choice: 'quadruped'" in capsys.readouterr().err
