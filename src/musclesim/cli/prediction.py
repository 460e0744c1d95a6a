"""The command predict: a declared set of predictions computed and written as the JSON the
scenarios ship (its handler next to its arguments)."""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from musclesim.cli.args import add_dask_args, add_fmus


def _cmd_predict(args: argparse.Namespace) -> int:
    from musclesim.batch import cluster_map
    from musclesim.cosim import check_fresh, replace_file
    from musclesim.prediction import load_declaration, predict

    declaration = load_declaration(args.declaration)
    check_fresh(args.fmus)
    start = time.monotonic()
    with cluster_map(args.scheduler, args.workers) as pmap:
        doc = predict(declaration, args.fmus, pmap,
                      lambda text: print(f"musclesim: {text}", file=sys.stderr))
    doc["seconds"] = round(time.monotonic() - start, 1)
    out = Path(args.out)
    replace_file(out, json.dumps(doc, indent=1) + "\n")
    for name, entry in doc["scenarios"].items():
        for metric, o in entry["outcomes"].items():
            iv = "no interval" if o["interval90"] is None else \
                f"[{o['interval90'][0]:.4g}, {o['interval90'][1]:.4g}]"
            value = "no value" if o["value"] is None else f"{o['value']:.4g}"
            study = "" if o["study"] is None else f" (the study: {o['study']:.4g})"
            print(f"{name} {metric} = {value} {iv} {o['unit']}{study}")
    print(f"wrote {out} in {doc['seconds']:.0f} s")
    return 0


def add_predict(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `predict` in subparsers `sub`."""
    q = sub.add_parser("predict", help="predict every outcome of a declared set of scenarios "
                       "with 90 %% intervals (the shipped fit's uncertainty and the diagnosis's "
                       "alternative models); write the JSON the scenarios ship")
    q.add_argument("declaration", help="the declaration (e.g. "
                   "scenarios/predictions/fast-actuation.toml)")
    q.add_argument("--out", required=True, help="the JSON file to write (the shipped one: the "
                   "declaration's name with .json, beside it)")
    add_dask_args(q)
    add_fmus(q)
    q.set_defaults(func=_cmd_predict)
