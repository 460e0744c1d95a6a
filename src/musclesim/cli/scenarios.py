"""The commands that build FMUs and run scenarios: build, run, export, sweep (each command's
handler next to its arguments)."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from musclesim.cli.args import add_scenario_args, positive


def _cmd_build(args: argparse.Namespace) -> int:
    from musclesim.cosim import build_all, loader_unavailable

    note = loader_unavailable(args.fmi)
    if note:
        print(f"musclesim: {note[0].upper()}{note[1:]}.", file=sys.stderr)
    for path in build_all(args.fmus, fmi=args.fmi):
        print(f"built {path}")
    return 0


def _cmd_run(args: argparse.Namespace) -> int:
    from musclesim.cosim import load_scenario, run_scenario
    from musclesim.prediction import SUMMARY_KEY, describe, summary_entry

    # the shipped predictions of this scenario, when the run is the one they were made for
    extra = summary_entry(load_scenario(args.scenario, args.set, args.stop_time))
    summary, res = run_scenario(args.scenario, args.out, args.fmus, args.set, args.stop_time,
                                host=args.host, isolate=args.isolate, extra=extra)
    out = Path(args.out)
    if summary["description"]:  # the file's words: overrides may have changed what it says
        print(summary["description"] + (f" (with --set {', '.join(args.set)})" if args.set else ""))
    for name, unit in summary["units"].items():  # a metric without a value: a warning says why
        value = summary[name]
        print(f"{name}: no value" if value is None else f"{name} = {value:.6g} {unit}")
    if (out / "results.png").is_file():  # the previous run's plot is gone: this run's, if drawn
        print(f"wrote {out / 'results.csv'}, {out / 'summary.json'} and {out / 'results.png'}")
    else:  # no plot of fewer than two rows
        print(f"wrote {out / 'results.csv'} and {out / 'summary.json'}")
    for line in describe(extra[SUMMARY_KEY]) if extra else ():
        print(line)
    for warning in summary["warnings"]:
        print(f"musclesim: warning from {warning}", file=sys.stderr)
    if res.error:
        print(f"musclesim: run stopped: {res.error} (results up to then are kept)", file=sys.stderr)
        return 1
    return 0


def _cmd_export(args: argparse.Namespace) -> int:
    from musclesim.cosim import check_fresh, load_scenario
    from musclesim.export import export_fmu, export_ssp

    s = load_scenario(args.scenario, args.set, args.stop_time)
    check_fresh(args.fmus)
    if args.ssp is not None:
        print(f"wrote {export_ssp(s, args.fmus, args.ssp)}")
    else:
        print(f"wrote {export_fmu(s, args.fmus, args.fmu, args.fmi)}")
    return 0


def _cmd_sweep(args: argparse.Namespace) -> int:
    from musclesim.batch import run_sweep

    summary = run_sweep(args.scenario, grid=args.grid, out=args.out, fmu_dir=args.fmus,
                        scheduler=args.scheduler, workers=args.workers, overrides=args.set,
                        stop_time=args.stop_time)
    print(json.dumps(summary, indent=2))
    return 1 if summary.get("failed") else 0


def add_build(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `build` in subparsers `sub`."""
    q = sub.add_parser("build", help="build every component into FMUs")
    q.add_argument("--fmus", help="folder to build into (default: fmus; fmus3 with --fmi 3)")
    q.add_argument("--fmi", type=int, choices=(2, 3), default=2,
                   help="FMI version: 2.0 co-simulation FMUs (default) or 3.0 ones, from the "
                   "same slaves; the runner runs either")
    q.set_defaults(func=_cmd_build)


def add_run(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `run` in subparsers `sub`."""
    q = sub.add_parser("run", help="run a scenario, write results.csv, summary.json, a plot")
    add_scenario_args(q)
    q.add_argument("--out", required=True, help="output folder")
    q.add_argument("--host", choices=("direct", "fmpy"), default="direct",
                   help="who calls the FMUs `musclesim build` made: this process directly "
                   "(default) or fmpy, through the FMI C API; the results are the same bits "
                   "(other FMUs always run on fmpy)")
    q.add_argument("--isolate", action="store_true",
                   help="run every instance in a child process of its own (FMUs you do not "
                   "trust: a crash ends the run with one sentence, the results so far kept; "
                   "slower). One instance: isolate = true in its scenario table")
    q.set_defaults(func=_cmd_run)


def add_export(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `export` in subparsers `sub`."""
    q = sub.add_parser("export", help="export a scenario as an SSP archive or as one FMU")
    add_scenario_args(q)
    to = q.add_mutually_exclusive_group(required=True)
    to.add_argument("--ssp", help="the .ssp file to write (SSP 1.0: the scenario's FMUs, wiring "
                    "and values)")
    to.add_argument("--fmu", help="the .fmu file to write: the whole scenario as one "
                    "co-simulation FMU (FMPy's container FMU; Jacobi scenarios)")
    q.add_argument("--fmi", type=int, choices=(2, 3), default=2,
                   help="with --fmu: FMI 2.0 (default) or 3.0 for the one FMU; the FMUs inside "
                   "are those in --fmus, of either version")
    q.set_defaults(func=_cmd_export)


def add_sweep(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `sweep` in subparsers `sub`."""
    q = sub.add_parser("sweep", help="run a scenario over a parameter grid on Dask")
    add_scenario_args(q)
    q.add_argument("--grid", action="append", default=[], metavar="INST.PARAM=START:STOP:N",
                   help="a grid axis (repeatable)")
    q.add_argument("--out", required=True, help="output folder (one result per case)")
    q.add_argument("--scheduler", help="address of an existing Dask scheduler")
    q.add_argument("--workers", type=positive, help="workers of the local cluster")
    q.set_defaults(func=_cmd_sweep)
