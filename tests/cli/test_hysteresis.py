"""The SMA wire's hysteresis commands' arguments (musclesim.cli.hysteresis): loops, drift,
identify, bench, each parsed with its defaults."""
import argparse

import pytest

from musclesim.cli import hysteresis


def parse(add, *argv):
    """`argv` parsed by a parser holding only the command `add` registers."""
    p = argparse.ArgumentParser(prog="musclesim")
    add(p.add_subparsers(dest="command", required=True))
    return p.parse_args([str(a) for a in argv])


def test_loops_needs_a_stress_and_bands(capsys):
    parsed = parse(hysteresis.add_loops, "loops", "--stress", "1.5e8", "--band", "40:80",
                   "--band", "50:90")
    assert (parsed.stress, parsed.band, parsed.model, parsed.json) == (1.5e8, ["40:80", "50:90"],
                                                                       None, False)
    with pytest.raises(SystemExit):
        parse(hysteresis.add_loops, "loops", "--stress", "1e8")
    assert "the following arguments are required: --band" in capsys.readouterr().err


def test_drift_compares_tests_1_13_and_25_of_25_rounds_by_default(capsys):
    parsed = parse(hysteresis.add_drift, "drift")
    assert (parsed.scenario, parsed.rounds, parsed.cycles, parsed.samples_per_cycle,
            parsed.compare) == ("sma-drift", 25, 20, 200, [1, 13, 25])
    assert parse(hysteresis.add_drift, "drift", "--compare", "2", "4").compare == [2, 4]
    with pytest.raises(SystemExit):
        parse(hysteresis.add_drift, "drift", "--rounds", "0")
    assert "0 must be at least 1" in capsys.readouterr().err


def test_identify_takes_records_and_an_output_file():
    parsed = parse(hysteresis.add_identify, "identify", "a", "b", "--out", "forc.csv",
                   "--validate")
    assert (parsed.records, parsed.out, parsed.validate) == (["a", "b"], "forc.csv", True)


def test_bench_times_the_preisach_core_only(capsys):
    assert parse(hysteresis.add_bench, "bench", "preisach", "--json").json is True
    with pytest.raises(SystemExit):
        parse(hysteresis.add_bench, "bench", "sma")
    assert "invalid choice: 'sma'" in capsys.readouterr().err
