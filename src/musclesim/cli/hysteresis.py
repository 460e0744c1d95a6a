"""The SMA wire's hysteresis commands: loops, drift, identify, bench (each command's handler next
to its arguments)."""
from __future__ import annotations

import argparse
import json

from musclesim.cli.args import positive


def _cmd_loops(args: argparse.Namespace) -> int:
    from musclesim.hysteresis import loops_main

    out = loops_main(args.stress, args.band, model_path=args.model, as_json=args.json,
                     plot_path=args.plot)
    print(json.dumps(out, indent=2) if args.json else out)
    return 0


def _cmd_drift(args: argparse.Namespace) -> int:
    from musclesim.hysteresis import DriftProtocol, drift_main

    protocol = DriftProtocol(rounds=args.rounds, cycles=args.cycles,
                             samples_per_cycle=args.samples_per_cycle,
                             compare=tuple(args.compare))
    protocol.check()
    print(drift_main(args.scenario, protocol, as_json=args.json))
    return 0


def _cmd_identify(args: argparse.Namespace) -> int:
    from musclesim.hysteresis import identify_main

    out = identify_main(args.records, args.out, validate=args.validate, as_json=args.json)
    print(json.dumps(out, indent=2) if args.json else out)
    return 0


def _cmd_bench(args: argparse.Namespace) -> int:
    from musclesim.hysteresis import format_preisach_timing, preisach_timing

    report = preisach_timing()
    print(json.dumps(report, indent=2) if args.json else format_preisach_timing(report))
    return 0


def add_loops(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `loops` in subparsers `sub`."""
    q = sub.add_parser("loops", help="steady strain loops of cycled temperature bands (SMA wire)")
    q.add_argument("--stress", type=float, required=True, help="constant stress [Pa]")
    q.add_argument("--band", action="append", required=True, metavar="T_LO:T_HI",
                   help="temperature band in C (repeatable)")
    q.add_argument("--model", help="FORC data file, or a wire parameter .toml (default: the "
                                   "reference wire)")
    q.add_argument("--plot", help="write the loops plot to this PNG")
    q.add_argument("--json", action="store_true", help="print JSON instead of text")
    q.set_defaults(func=_cmd_loops)


def add_drift(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `drift` in subparsers `sub`."""
    q = sub.add_parser("drift", help="the long-duration drift test: RMSE between the "
                                     "averaged loops of tests 1, 13 and 25 per stress")
    q.add_argument("scenario", nargs="?", default="sma-drift",
                   help="scenario whose instance 'wire' sets the drift (default: the shipped "
                        "%(default)s)")
    q.add_argument("--rounds", type=positive, default=25, help="rounds of the five stresses")
    q.add_argument("--cycles", type=positive, default=20, help="cycles per test")
    q.add_argument("--samples-per-cycle", type=positive, default=200,
                   help="temperature samples per 20 s cycle")
    q.add_argument("--compare", type=positive, nargs="+", default=[1, 13, 25],
                   metavar="TEST", help="tests whose averaged loops are compared, in pairs")
    q.add_argument("--json", action="store_true", help="print JSON instead of text")
    q.set_defaults(func=_cmd_drift)


def add_identify(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `identify` in subparsers `sub`."""
    q = sub.add_parser("identify", help="FORC surfaces from identification records (SMA wire)")
    q.add_argument("records", nargs="+",
                   help="sweep output folder, run folders or results.csv files (one per stress)")
    q.add_argument("--out", required=True, help="the FORC data file to write")
    q.add_argument("--validate", action="store_true",
                   help="also report errors against the virtual wire")
    q.add_argument("--json", action="store_true", help="print JSON instead of text")
    q.set_defaults(func=_cmd_identify)


def add_bench(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `bench` in subparsers `sub`."""
    q = sub.add_parser("bench", help="timing benchmarks of the pure cores (on demand)")
    q.add_argument("core", choices=["preisach"], help="the core to time")
    q.add_argument("--json", action="store_true", help="print JSON instead of text")
    q.set_defaults(func=_cmd_bench)
