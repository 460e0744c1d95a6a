"""The command line's shared arguments (musclesim.cli.args): the argparse types' hand cases and
the options every command that runs a scenario, reads FMUs or uses Dask shares."""
import argparse

import pytest

from musclesim.cli import args


@pytest.mark.parametrize("text, value", [("0", 0), ("7", 7), (" 12", 12)])
def test_count_takes_whole_numbers_from_zero(text, value):
    assert args.count(text) == value


@pytest.mark.parametrize("text, message", [("-1", "-1 must be at least 0"),
                                           ("2.5", "'2.5' is not a whole number"),
                                           ("many", "'many' is not a whole number")])
def test_count_refuses_the_rest(text, message):
    with pytest.raises(argparse.ArgumentTypeError, match=message):
        args.count(text)


def test_positive_starts_at_one():
    assert args.positive("1") == 1
    with pytest.raises(argparse.ArgumentTypeError, match="0 must be at least 1"):
        args.positive("0")
    with pytest.raises(argparse.ArgumentTypeError, match="-3 must be at least 0"):
        args.positive("-3")


@pytest.mark.parametrize("text, value", [("10", 10.0), ("12.5", 12.5), ("1e3", 1000.0)])
def test_a_duration_is_at_least_one_reference_period(text, value):
    assert args.duration(text) == value


@pytest.mark.parametrize("text, message", [
    ("9.99", "9.99 s is shorter than one period of the bench's reference"),
    ("nan", "nan s is shorter"), ("inf", "inf s is shorter"),
    ("ten", "'ten' is not a number of seconds")])
def test_a_duration_refuses_short_and_non_finite_ones(text, message):
    with pytest.raises(argparse.ArgumentTypeError, match=message):
        args.duration(text)


def test_the_shared_options_and_their_defaults():
    p = argparse.ArgumentParser()
    args.add_scenario_args(p)
    args.add_dask_args(p)
    parsed = p.parse_args(["s.toml"])
    assert vars(parsed) == {"scenario": "s.toml", "set": [], "stop_time": None, "fmus": "fmus",
                            "scheduler": None, "workers": None}
    parsed = p.parse_args(["s.toml", "--set", "a.b=1", "--set", "c.d=2", "--stop-time", "3",
                           "--fmus", "f", "--scheduler", "tcp://x:1", "--workers", "2"])
    assert (parsed.set, parsed.stop_time, parsed.fmus, parsed.scheduler, parsed.workers) == (
        ["a.b=1", "c.d=2"], 3.0, "f", "tcp://x:1", 2)
    with pytest.raises(SystemExit):
        p.parse_args(["s.toml", "--workers", "0"])
