"""The command benchmark-diagnosis's arguments (musclesim.cli.benchmark): its defaults, and the
counts and durations it refuses before any work."""
import argparse

import pytest

from musclesim.cli import benchmark, main


def parse(add, *argv):
    """`argv` parsed by a parser holding only the command `add` registers."""
    p = argparse.ArgumentParser(prog="musclesim")
    add(p.add_subparsers(dest="command", required=True))
    return p.parse_args([str(a) for a in argv])


def test_forty_own_cases_from_seed_1_by_default():
    parsed = parse(benchmark.add_benchmark_diagnosis, "benchmark-diagnosis", "--out", "o")
    assert (parsed.cases, parsed.seed, parsed.bench, parsed.duration, parsed.multiplier,
            parsed.crawler, parsed.scenarios, parsed.fmus) == (40, 1, "own", None, 0, 0,
                                                               None, "fmus")


def test_refused_counts_and_durations(capsys, tmp_path):
    for argv, message in ((["--duration", "5"], "5 s is shorter than one period"),
                          (["--cases", "-1"], "-1 must be at least 0"),
                          (["--multiplier", "0"], "0 must be at least 1"),
                          (["--bench", "bench"], "invalid choice: 'bench'")):
        with pytest.raises(SystemExit):
            parse(benchmark.add_benchmark_diagnosis, "benchmark-diagnosis", "--out", "o", *argv)
        assert message in capsys.readouterr().err
    # zero cases only with crawler cases: main says so, naming the option, before any work
    with pytest.raises(SystemExit) as info:
        main(["benchmark-diagnosis", "--out", str(tmp_path / "o"), "--cases", "0"])
    assert info.value.code == 2 and not (tmp_path / "o").exists()
    assert "argument --cases: 0 must be at least 1 (0 only with --crawler)" in \
        capsys.readouterr().err
