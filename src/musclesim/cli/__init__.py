"""The `musclesim` command line: build, run, export, sweep, loops, identify, drift, dataset,
diagnose, calibrate, predict, benchmark-diagnosis, bench, linear, characterise, table.

The top layer: it parses arguments, calls the public interfaces of the layers below (cosim, batch,
analysis, hysteresis, diagnosis, prediction, benchmark) and prints; nothing imports it. Each
command's arguments sit next to its handler, by the layer it calls: scenarios (build, run, export,
sweep), hysteresis (loops, drift, identify, bench), diagnosis (dataset, diagnose, calibrate),
prediction (predict), benchmark (benchmark-diagnosis), analysis (table, characterise, linear);
args holds the shared arguments.

Mistakes a user can fix end in one sentence on stderr and exit status 2; a failed simulation
exits with status 1 after writing the results it reached.
"""
from __future__ import annotations

import argparse
import os
import sys

from musclesim.cli import analysis, benchmark, diagnosis, hysteresis, prediction, scenarios
from musclesim.errors import UserError

__all__ = ["main"]

# the commands in the order `musclesim --help` lists them
_COMMANDS = [scenarios.add_build, scenarios.add_run, scenarios.add_export, scenarios.add_sweep,
             hysteresis.add_loops, hysteresis.add_drift, hysteresis.add_identify,
             diagnosis.add_dataset, diagnosis.add_diagnose, diagnosis.add_calibrate,
             prediction.add_predict,
             benchmark.add_benchmark_diagnosis, analysis.add_table, hysteresis.add_bench,
             analysis.add_characterise, analysis.add_linear]


def _parser() -> argparse.ArgumentParser:
    from musclesim import __version__

    p = argparse.ArgumentParser(
        prog="musclesim", description="Artificial-muscle physics as FMI co-simulation components: "
        "build the FMUs, run and sweep scenarios, analyse, and diagnose a model's gap to a bench.")
    p.add_argument("--version", action="version", version=f"musclesim {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    for add in _COMMANDS:
        add(sub)
    return p


# every command's outputs, checked before the command does any work: (option, folder or file)
_OUTPUTS = {"build": [("fmus", "dir")], "run": [("out", "dir")],
            "export": [("ssp", "file"), ("fmu", "file")],
            "sweep": [("out", "dir")], "loops": [("plot", "file")], "identify": [("out", "file")],
            "diagnose": [("out", "dir")], "calibrate": [("out", "dir")],
            "predict": [("out", "file")],
            "benchmark-diagnosis": [("out", "dir")],
            "table": [("out", "dir")], "characterise": [("out", "dir"), ("write", "file")],
            "linear": [("write", "file")]}


def _check_outputs(args: argparse.Namespace) -> None:
    from musclesim.cosim import check_output_dir, check_output_file

    for option, kind in _OUTPUTS.get(args.command, ()):
        path = getattr(args, option)
        if path is None:
            continue
        if kind == "dir" or (args.command == "linear" and args.system == "pneumatic"):
            check_output_dir(path, f"--{option}")
        else:
            check_output_file(path, f"--{option}")


def main(argv: list[str] | None = None) -> int:
    """Entry point of the `musclesim` console script: run the command `argv` (default: sys.argv's).

    Exit status: 0 done, 1 a run or case failed (its results kept), 2 a mistake in the input,
    130 / 143 stopped by SIGINT / SIGTERM (what was written so far is kept).
    """
    args = _parser().parse_args(argv)
    if args.command == "build" and args.fmus is None:  # each FMI version its own folder
        args.fmus = "fmus" if args.fmi == 2 else "fmus3"
    if args.command == "build" and "musclesim.fmu.compiled" not in sys.modules:
        # Writing a model description runs each slave's setup and outputs once (their start
        # values): compiled, that compiles every component's cores, some 17 s on a fresh
        # machine, for components a run may never use. This process, which has not imported the
        # cores yet, runs them as plain Python: the same start values (tests/cli/test_cli.py);
        # each run compiles what it uses. A process that imported them keeps its mode.
        os.environ.setdefault("MUSCLESIM_COMPILE", "0")
    if getattr(args, "cases", None) == 0 and not args.crawler:  # benchmark-diagnosis
        args.subparser.error("argument --cases: 0 must be at least 1 (0 only with --crawler)")
    try:
        from musclesim.cosim import Interrupted, interruptible, locate_scenario

        if isinstance(getattr(args, "scenario", None), str):  # a file, or a shipped one's name
            args.scenario = str(locate_scenario(args.scenario))
        with interruptible():
            _check_outputs(args)
            return args.func(args)
    except UserError as exc:
        print(f"musclesim: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # Ctrl-C before the handlers were in place (while importing);
        # first, since the name Interrupted below is unbound until that import is done
        print("musclesim: interrupted by SIGINT before any work", file=sys.stderr)
        return 130
    except Interrupted as exc:
        print(f"musclesim: {exc}; what was written so far is kept", file=sys.stderr)
        return exc.exit_code

