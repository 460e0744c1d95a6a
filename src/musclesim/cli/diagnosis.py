"""The diagnosis's commands: dataset check, diagnose, calibrate (each command's handler next to
its arguments)."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from musclesim.cli.args import add_dask_args, add_fmus
from musclesim.errors import UserError


def _cmd_dataset_check(args: argparse.Namespace) -> int:
    from musclesim.diagnosis import load_dataset

    ds = load_dataset(args.dataset, check_model=args.model, fmu_dir=args.fmus)
    train, held = ds.parts()
    kind = "scalar-only" if ds.time is None else \
        f"{len(ds.time)} samples, {len(ds.columns)} columns"
    print(f"{ds.path}: OK ({kind}; experiments {', '.join(ds.experiments)}; "
          f"train {', '.join(train)}; held out {', '.join(held) or 'nothing'})")
    return 0


def _cmd_diagnose(args: argparse.Namespace) -> int:
    from musclesim.batch import cluster_map
    from musclesim.cosim import check_fresh
    from musclesim.diagnosis import diagnose, load_dataset, write_report

    models: dict[str, str] = {}
    for item in args.model:
        experiment, sep, ref = item.rpartition("=")
        if not ref:
            raise UserError(f"--model {item!r}: give SCENARIO or EXPERIMENT=SCENARIO")
        models[experiment if sep else "*"] = ref
    ds = load_dataset(args.dataset, check_model=True, fmu_dir=args.fmus, models=models)
    if not ds.parts()[1]:
        raise UserError(f"data set {ds.path} holds nothing out (held_out = []): musclesim "
                        "diagnose judges on a held-out part; fit its open values with musclesim "
                        "calibrate")
    check_fresh(args.fmus)
    traces: dict = {}
    with cluster_map(args.scheduler, args.workers) as pmap:
        report = diagnose(ds, args.fmus, pmap,
                          lambda text: print(f"musclesim: {text}", file=sys.stderr), traces)
    paths = write_report(args.out, report, traces)
    document = report.to_json()  # the Report as report.json holds it
    print(f"verdict: {document['verdict']} ({document['explanation']})")
    print(f"next step: {document['next_step']}")
    print("wrote " + ", ".join(str(p) for p in paths))
    for warning in document["warnings"]:  # values on a bound: the model's form to question
        print(f"musclesim: warning: {warning}", file=sys.stderr)
    return 0


def _cmd_calibrate(args: argparse.Namespace) -> int:
    from musclesim.batch import cluster_map
    from musclesim.cosim import check_fresh
    from musclesim.diagnosis import (calibrate, calibration_bound_sentence,
                                     calibration_markdown, load_dataset)

    ds = load_dataset(args.dataset, check_model=True, fmu_dir=args.fmus)
    check_fresh(args.fmus)
    with cluster_map(args.scheduler, args.workers) as pmap:
        report = calibrate(ds, args.fmus, pmap,
                           lambda text: print(f"musclesim: {text}", file=sys.stderr))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "calibration.json").write_text(json.dumps(report, indent=1) + "\n")
    text = calibration_markdown(report)
    (out / "calibration.md").write_text(text)
    print(text, end="")
    print(f"wrote {out / 'calibration.json'}, {out / 'calibration.md'}")
    if sentence := calibration_bound_sentence(report):
        print(sentence)
    return 0


def add_dataset(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `dataset` (its action check) in subparsers `sub`."""
    q = sub.add_parser("dataset", help="measured data sets (sim-to-real diagnosis)")
    actions = q.add_subparsers(dest="action", required=True)
    c = actions.add_parser("check", help="validate a data set, reporting every problem at once")
    c.add_argument("dataset", help="data set directory (manifest.toml [+ data.csv])")
    c.add_argument("--model", action="store_true",
                   help="also check it against its scenario and the FMUs")
    add_fmus(c)
    c.set_defaults(func=_cmd_dataset_check)


def add_diagnose(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `diagnose` in subparsers `sub`."""
    q = sub.add_parser("diagnose", help="sim-to-real gap diagnosis of a measured data set")
    q.add_argument("dataset", help="data set folder (manifest.toml + data.csv)")
    q.add_argument("--out", required=True, help="folder for report.json, report.md and plots")
    q.add_argument("--model", action="append", default=[], metavar="[EXPERIMENT=]SCENARIO",
                   help="diagnose against this scenario instead of the manifest's (for every "
                   "experiment, or the one named; repeatable)")
    add_dask_args(q)
    add_fmus(q)
    q.set_defaults(func=_cmd_diagnose)


def add_calibrate(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `calibrate` in subparsers `sub`."""
    q = sub.add_parser("calibrate", help="fit the open values a scalar-only data set names "
                       "([[calibrate]]) to its training metrics; predict the held-out ones")
    q.add_argument("dataset", help="data set folder (manifest.toml)")
    q.add_argument("--out", required=True, help="folder for calibration.json and calibration.md")
    add_dask_args(q)
    add_fmus(q)
    q.set_defaults(func=_cmd_calibrate)
