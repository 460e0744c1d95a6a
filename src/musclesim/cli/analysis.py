"""The analysis commands: table, characterise, linear (each command's handler next to its
arguments)."""
from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import cast

from musclesim.cli.args import add_dask_args, add_fmus
from musclesim.errors import UserError


def _cmd_table(args: argparse.Namespace) -> int:
    from musclesim.analysis import sma_position

    report = sma_position(args.out, args.scenario, args.fmus, args.stop_time,
                          args.scheduler, args.workers, args.only, run=not args.no_run)
    for name, stats in report.items():
        if stats["cells"] == 0:
            print(f"{name}: no case finished yet")
        else:
            print(f"{name}: {stats['cells']} cells, mean strain RMSE {stats['rmse'][0]:.4g} "
                  f"(std {stats['rmse'][1]:.3g}), {stats['percent'][0]:.3g} % of the maximum "
                  "reference strain")
        for cid, error in stats["failed"].items():
            print(f"  case {cid} failed: {error}")
    print(f"wrote the tables (CSV, Markdown) and the per-case figures into {args.out}")
    return 1 if any(stats["failed"] for stats in report.values()) else 0


def _cmd_characterise(args: argparse.Namespace) -> int:
    from musclesim.analysis import ELONGATION_TARGET, gait_references, gait_references_toml
    from musclesim.cosim import replace_file, run_scenario

    summary, res = run_scenario(args.scenario, args.out, args.fmus, args.set)
    if res.error:
        raise UserError(f"{args.scenario}: the characterisation run stopped: {res.error}")
    refs = gait_references(res)
    print(f"central: {refs['p_central']:.1f} Pa for {ELONGATION_TARGET:g} m "
          f"elongation ({refs['elongation_at_ramp_end']:.4f} m at the end of the ramp)")
    for i, where in ((1, "back"), (2, "front")):
        print(f"{where} extremal: firm ground contact from {refs[f'p_firm{i}']:.1f} Pa, "
              f"reference {refs[f'p_anchor{i}']:.1f} Pa")
    print(f"wrote the run to {args.out}")
    if args.write:
        replace_file(args.write, gait_references_toml(refs, args.scenario))
        print(f"wrote the gait references to {args.write}", file=sys.stderr)
    return 0


def _cmd_linear(args: argparse.Namespace) -> int:
    from musclesim.analysis import (bending, crawler, format_bending, format_crawler,
                                    format_pneumatic, format_sma_load, format_sma_thermal,
                                    gain_table_toml, load_gains_toml, pneumatic,
                                    pneumatic_gains_toml, sma_load, sma_thermal)
    from musclesim.cosim import check_fresh, replace_file

    if args.system == "crawler":
        toml: Callable[..., str] | None
        report, text, toml = crawler(), format_crawler, None
    elif args.system == "bending":
        report, text, toml = bending(), format_bending, None
    elif args.system == "sma-thermal":
        report, text, toml = sma_thermal(), format_sma_thermal, gain_table_toml
    elif args.system == "sma-load":
        check_fresh(args.fmus)
        report, text, toml = sma_load(args.fmus), format_sma_load, load_gains_toml
    else:
        check_fresh(args.fmus)
        report, text, toml = pneumatic(args.fmus), format_pneumatic, pneumatic_gains_toml
    if args.write and toml is None:
        raise UserError(f"--write is for sma-thermal, sma-load and pneumatic, not {args.system}")
    written: list[Path] = []
    if args.write and args.system == "pneumatic":  # one file per actuator kind, into a folder
        Path(args.write).mkdir(parents=True, exist_ok=True)
        for actuator in report["loops"]:
            written.append(Path(args.write) / f"pneumatic-{actuator}-pid.toml")
            replace_file(written[-1], cast(Callable[..., str], toml)(report, actuator))
    elif args.write:
        written.append(Path(args.write))
        replace_file(written[-1], cast(Callable[..., str], toml)(report))
    print(json.dumps(report, indent=2) if args.json else text(report))
    for path in written:
        print(f"wrote the gains to {path}", file=sys.stderr)
    return 0


def add_table(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `table` in subparsers `sub`."""
    q = sub.add_parser("table", help="the study's tables: sma-position (the position-control "
                                     "matrix, on Dask)")
    q.add_argument("table", choices=["sma-position"], help="which tables")
    q.add_argument("--out", required=True, help="folder for the cases, tables and figures")
    q.add_argument("--scenario", default="sma-position-control",
                   help="the position-control scenario the cases override (default: the shipped "
                   "%(default)s)")
    q.add_argument("--stop-time", type=float, help="shorter runs than the scenario's 550 s")
    q.add_argument("--only", action="append", choices=["constant-stress", "stress-aware",
                                                       "stress-ignored"],
                   help="run only these tables (repeatable)")
    q.add_argument("--no-run", action="store_true",
                   help="run no case: write the tables and figures of the cases finished so far")
    add_dask_args(q)
    add_fmus(q)
    q.set_defaults(func=_cmd_table)


def add_characterise(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `characterise` in subparsers `sub`."""
    q = sub.add_parser("characterise", help="the crawler's characterisation: the gait's pressure "
                                            "references")
    q.add_argument("scenario", nargs="?", default="crawler-characterisation",
                   help="the characterisation scenario (default: the shipped %(default)s)")
    q.add_argument("--out", default="results/crawler-characterisation",
                   help="folder for the run's results (default: %(default)s)")
    q.add_argument("--write", metavar="FILE", help="write the references (TOML) the gait "
                                                   "scenarios read")
    q.add_argument("--set", action="append", default=[], metavar="INST.PARAM=VALUE",
                   help="override a parameter (repeatable)")
    add_fmus(q)
    q.set_defaults(func=_cmd_characterise)


def add_linear(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `linear` in subparsers `sub`."""
    q = sub.add_parser("linear", help="linear analysis with python-control")
    q.add_argument("system", choices=["crawler", "sma-thermal", "sma-load", "pneumatic",
                                      "bending"],
                   help="the system to analyse")
    q.add_argument("--json", action="store_true", help="print JSON instead of text")
    q.add_argument("--write", metavar="FILE", help="sma-thermal, sma-load: write the controller "
                   "parameters (TOML) a scenario can read; pneumatic: a folder that receives "
                   "pneumatic-central-pid.toml and pneumatic-extremal-pid.toml")
    add_fmus(q)
    q.set_defaults(func=_cmd_linear)
