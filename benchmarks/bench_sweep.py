"""Benchmark: the 100 cases of scenarios/crawler-sweep-frequency.toml (60 s each) run three ways
in one process, timed: in chunks on a local cluster (the default: `musclesim.batch.chunks`, each
chunk one compiled pass), one case a task on the same cluster (as before chunks), and in this
process (``--workers 1``, no cluster).

    .venv/bin/python benchmarks/bench_sweep.py [--fmus fmus] [--workers 2] [--json out.json]

Each time is the whole `musclesim sweep` (starting its cluster, writing every case's folder,
sweep.csv and the plot); a first untimed sweep of two cases compiles or loads the compiled code.
The three sweep.csv files must hold the same numbers (checked).
"""
import argparse
import csv
import json
import tempfile
import time
from pathlib import Path

from musclesim.batch import cases, sweep
from musclesim.cosim import check_fresh

ROOT = Path(__file__).resolve().parents[1]
SWEEP = ROOT / "scenarios" / "crawler-sweep-frequency.toml"


def _timed(out, fmu_dir, workers):
    t0 = time.perf_counter()
    summary = sweep.run(SWEEP, [], out, fmu_dir=fmu_dir, workers=workers)
    assert summary["completed"] == summary["cases"], summary["failed"]
    return time.perf_counter() - t0


def _rows(out):
    with (out / "sweep.csv").open(newline="") as f:
        return sorted(map(tuple, csv.reader(f)))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--fmus", default=str(ROOT / "fmus"))
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--json", help="write the times here")
    args = p.parse_args()
    check_fresh(args.fmus)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        sweep.run(SWEEP, ["inputs.f_f=0.5,1"], tmp / "warm", fmu_dir=args.fmus, workers=1)
        times = {"chunks": _timed(tmp / "chunks", args.fmus, args.workers)}
        bound = cases.CHUNK_VALUES
        cases.CHUNK_VALUES = 1  # every chunk one case: one task a case
        try:
            times["one_case_a_task"] = _timed(tmp / "single", args.fmus, args.workers)
        finally:
            cases.CHUNK_VALUES = bound
        times["in_process"] = _timed(tmp / "here", args.fmus, 1)
        assert _rows(tmp / "chunks") == _rows(tmp / "single") == _rows(tmp / "here")
    result = {"cases": 100, "workers": args.workers, "seconds": times,
              "one_case_a_task_over_chunks": times["one_case_a_task"] / times["chunks"]}
    print(json.dumps(result, indent=2))
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
