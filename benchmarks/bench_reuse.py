"""Time of a scenario run with its FMUs unpacked anew (as `musclesim run` does) against runs
inside `reuse_fmus` (as the diagnosis's fits do), measured in one process; prints the ratio.

    .venv/bin/python benchmarks/bench_reuse.py [--runs N] [--stop-time T] [--fmus DIR]
"""
import argparse
import statistics
import time
from pathlib import Path

from musclesim.cosim import Master, check_fresh, load_scenario, reuse_fmus

ROOT = Path(__file__).resolve().parents[1]


def _times(s, fmu_dir, runs, reuse):
    out = []
    for _ in range(runs):
        t0 = time.perf_counter()
        if reuse:
            Master(s, fmu_dir).run()
        else:
            with reuse_fmus():  # a block per run: unpacked anew every time, like a lone run
                Master(s, fmu_dir).run()
        out.append(time.perf_counter() - t0)
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=10)
    p.add_argument("--stop-time", type=float, default=20.0)
    p.add_argument("--fmus", default=str(ROOT / "fmus"))
    args = p.parse_args()
    check_fresh(args.fmus)
    s = load_scenario(ROOT / "scenarios" / "sma-bench-tracking.toml", (), args.stop_time)
    fresh = _times(s, args.fmus, args.runs, reuse=False)
    with reuse_fmus():
        reused = _times(s, args.fmus, args.runs, reuse=True)
    a, b = statistics.median(fresh), statistics.median(reused)
    print(f"sma-bench-tracking, {args.stop_time:g} s, {args.runs} runs each: unpacked per run "
          f"{a * 1e3:.0f} ms, reused {b * 1e3:.0f} ms (median); ratio {a / b:.2f}")


if __name__ == "__main__":
    main()
