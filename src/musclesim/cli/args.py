"""The command line's shared arguments (FMU folder, scenario and overrides, Dask) and argparse
types (counts, durations)."""
from __future__ import annotations

import argparse
import math


def add_fmus(q: argparse.ArgumentParser) -> None:
    """Give parser `q` the option --fmus (the folder of built FMUs)."""
    q.add_argument("--fmus", default="fmus", help="folder of built FMUs (default: fmus)")


def add_scenario_args(q: argparse.ArgumentParser) -> None:
    """Give parser `q` a scenario, --set, --stop-time and --fmus."""
    q.add_argument("scenario", help="scenario TOML file (for sweep: or a sweep file), or the "
                   "name of a shipped one (e.g. crawler-ideal)")
    q.add_argument("--set", action="append", default=[], metavar="INST.PARAM=VALUE",
                   help="override a parameter (repeatable)")
    q.add_argument("--stop-time", type=float, help="replace the scenario's stop time [s]")
    add_fmus(q)


def add_dask_args(q: argparse.ArgumentParser) -> None:
    """Give parser `q` the Dask options --scheduler and --workers."""
    q.add_argument("--scheduler", help="address of a running Dask scheduler (default: a "
                   "local cluster)")
    q.add_argument("--workers", type=positive,
                   help="local worker processes (default: cores; 1: in this process, no "
                   "cluster)")


def count(text: str) -> int:
    """argparse type: the integer `text` says, at least 0."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"{text} must be at least 0")
    return value


def positive(text: str) -> int:
    """argparse type: the integer `text` says, at least 1."""
    value = count(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text} must be at least 1")
    return value


def duration(text: str) -> float:
    """argparse type: the seconds `text` says, recorded per independent bench case, at least
    one reference period (10 s)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not math.isfinite(value) or value < 10:
        raise argparse.ArgumentTypeError(f"{text} s is shorter than one period of the bench's "
                                         "reference (10 s)")
    return value

