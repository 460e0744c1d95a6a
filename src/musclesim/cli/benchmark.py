"""The command benchmark-diagnosis: the diagnosis checked blind on virtual hardware (its
handler next to its arguments)."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from musclesim.cli.args import add_dask_args, add_fmus, count, duration, positive


def _cmd_benchmark_diagnosis(args: argparse.Namespace) -> int:
    from musclesim.batch import cluster_map
    from musclesim.cosim import check_fresh, shipped_scenarios
    from musclesim.benchmark import run_blind_benchmark

    check_fresh(args.fmus)
    with cluster_map(args.scheduler, args.workers) as pmap:
        scores = run_blind_benchmark(args.cases, args.seed, args.out, args.fmus,
                                     args.scenarios or shipped_scenarios(),
                                     pmap,
                                     lambda text: print(f"musclesim: {text}", file=sys.stderr),
                                     bench=args.bench, duration=args.duration,
                                     multiplier=args.multiplier, crawler=args.crawler,
                                     calibration=args.calibrate, resume=args.resume)
    print(json.dumps({k: v for k, v in scores.items() if k != "per_case"}, indent=2))
    print(f"wrote {Path(args.out) / 'scores.json'} (per-case table inside)")
    if args.calibrate:
        print(f"wrote the calibration {args.calibrate}")
    return 0


def add_benchmark_diagnosis(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    """The command `benchmark-diagnosis` in subparsers `sub`."""
    q = sub.add_parser("benchmark-diagnosis",
                       help="blind check of the diagnosis on virtual hardware with hidden effects")
    q.add_argument("--cases", type=count, default=40,
                   help="number of cases (default 40; 0 with --crawler: crawler cases only)")
    q.add_argument("--seed", type=int, default=1, help="seed of the hidden truths (default 1)")
    q.add_argument("--out", required=True, help="folder for the cases, key and scores.json")
    q.add_argument("--scenarios", help="folder of the bench scenarios (default: the shipped "
                   "ones)")
    q.add_argument("--bench", choices=["own", "independent", "family", "crawler-family"],
                   default="own",
                   help="own: the library's FMUs with hidden effects (default); independent: "
                        "an SMA bench written apart from the library (scores under "
                        "'independent' in scores.json); family, crawler-family: SMA or crawler "
                        "benches of many forms, scored by the calibrated sets (under the "
                        "bench's name)")
    q.add_argument("--calibrate", metavar="FILE", default=None,
                   help="family benches: build the sets' calibration from these cases and "
                        "write it to FILE (the shipped ones: src/musclesim/diagnosis/"
                        "calibrations/<scenario>.json; the SMA's 720 cases took 36 min on 2 "
                        "cores, the crawler's 540 about 2 h 20 min)")
    q.add_argument("--resume", action="store_true",
                   help="go on with a run in --out that stopped, the same --seed, --cases, "
                        "--bench and --duration: cases already diagnosed are kept")
    q.add_argument("--duration", type=duration, default=None,
                   help="independent or family benches: seconds recorded per case (default "
                        "120 for SMA, 12 for the crawler)")
    q.add_argument("--multiplier", type=positive, default=0, metavar="N",
                   help="own bench: N extra cases on the capstan multiplier's bench "
                        "(default none)")
    q.add_argument("--crawler", type=positive, default=0, metavar="N",
                   help="independent bench: N extra cases on its pneumatic crawler, 12 s each "
                        "(default none; scores also per bench)")
    add_dask_args(q)
    add_fmus(q)
    q.set_defaults(func=_cmd_benchmark_diagnosis, subparser=q)
