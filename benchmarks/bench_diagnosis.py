"""Wall time of a diagnosis with its fits on a local Dask cluster (every simulation a task, as
`musclesim diagnose` runs them) against the same diagnosis with the fits one after the other in
this process, measured in one run; prints each stage's time, the ratio, and whether the two
reports are the same (they should be, to the bit). Both are also given in units of a reference
measured in the same run: one nominal run of the model the diagnosis fits in (every measured
signal replayed), in this process, the fastest of three, so that a machine's own speed (a
shared host's varies by half within an hour) is told from the diagnosis's.

    .venv/bin/python benchmarks/bench_diagnosis.py [DATASET] [--workers 2] [--fmus DIR] [--json FILE]

DATASET defaults to the worked example scenarios/data/sma-independent-thermocouple-lag (120 s
of the 50 Hz SMA tracking bench). Run it on a quiet machine; nothing here is part of the tests.
"""
import argparse
import json
import time
from pathlib import Path

from musclesim.batch import dask_client, dask_map, serial_map
from musclesim.cosim import check_fresh, reuse_fmus
from musclesim.diagnosis import diagnose, load_dataset
from musclesim.diagnosis.problem import Problem
from musclesim.diagnosis.simulate import simulate

ROOT = Path(__file__).resolve().parents[1]


def timed(ds, fmu_dir, pmap):
    """(report.json's content, seconds in all, [(stage, seconds from the start)])."""
    t0, stages = time.perf_counter(), []
    report = diagnose(ds, fmu_dir, pmap, lambda text: stages.append(
        (text, time.perf_counter() - t0)))
    return report.to_json(), time.perf_counter() - t0, stages


def reference(ds, fmu_dir):
    """Seconds of one nominal run of the model with every measured signal replayed, here (the
    fastest of three, its FMUs unpacked once)."""
    unit = Problem(ds, fmu_dir).replayed()
    with reuse_fmus():
        simulate(unit, {}, fmu_dir)
        times = []
        for _ in range(3):
            t0 = time.perf_counter()
            simulate(unit, {}, fmu_dir)
            times.append(time.perf_counter() - t0)
    return min(times)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("dataset", nargs="?",
                   default=str(ROOT / "scenarios" / "data" / "sma-independent-thermocouple-lag"))
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--fmus", default=str(ROOT / "fmus"))
    p.add_argument("--json", help="also write the numbers to this file")
    args = p.parse_args()
    check_fresh(args.fmus)
    ds = load_dataset(args.dataset, check_model=True, fmu_dir=args.fmus)
    ref = reference(ds, args.fmus)
    serial, t_serial, s_serial = timed(ds, args.fmus, serial_map)
    with dask_client(None, args.workers) as client:
        parallel, t_parallel, s_parallel = timed(ds, args.fmus, dask_map(client))
    same = json.dumps(serial, sort_keys=True, default=float) == json.dumps(
        parallel, sort_keys=True, default=float)
    print(f"{Path(args.dataset).name}: verdict {parallel['verdict']}")
    for (text, a), (_, b) in zip(s_serial, s_parallel):
        print(f"  {text[:60]:60s} starts at {a:6.1f} s here, {b:6.1f} s on Dask")
    print(f"in all: {t_serial:.1f} s one fit after another here, {t_parallel:.1f} s on "
          f"{args.workers} Dask workers (cluster start not counted): ratio "
          f"{t_serial / t_parallel:.2f}; the same report: {same}")
    print(f"reference, one nominal run here: {ref:.3f} s; the diagnosis took "
          f"{t_serial / ref:.0f} of them here, {t_parallel / ref:.0f} on Dask")
    if args.json:
        Path(args.json).write_text(json.dumps(
            {"dataset": args.dataset, "workers": args.workers, "serial_s": t_serial,
             "dask_s": t_parallel, "ratio": t_serial / t_parallel, "same_report": same,
             "reference_run_s": ref,
             "stages": [{"stage": t, "serial_s": a, "dask_s": b}
                        for (t, a), (_, b) in zip(s_serial, s_parallel)]}, indent=2) + "\n")
    if not same:
        raise SystemExit("the reports differ: the map changed a result")


if __name__ == "__main__":
    main()
