"""Real-time factor of the SMA position-control scenario (issue 5, §position-control) and the time
per communication step split by FMU.

    .venv/bin/python benchmarks/bench_position.py [--stop-time 550] [--json FILE]

First run: the master as `musclesim run` uses it, timed as a whole -> real-time factor
(simulated time / wall time; above 1 = faster than real time). Second run: every FMU's
fmi2DoStep and the exchanges timed separately (the timers add a little overhead; the split is
what it is for). Run it on a quiet machine; nothing here is part of the test suite.
"""
import argparse
import json
import time
from pathlib import Path

from musclesim.cosim import Master, load_scenario

ROOT = Path(__file__).resolve().parents[1]


def timed_run(s, fmu_dir, split):
    m = Master(s, fmu_dir)
    spent = {}
    if split:
        instantiate = m._instantiate

        def wrap(tmp):
            instantiate(tmp)
            for inst in m.instances.values():
                raw, name = inst.do_step, inst.name

                def do_step(c, t, h, flag, raw=raw, name=name):
                    t0 = time.perf_counter()
                    status = raw(c, t, h, flag)
                    spent[name] = spent.get(name, 0.0) + time.perf_counter() - t0
                    return status
                inst.do_step = do_step
        m._instantiate = wrap
        exchange = m._exchange

        def timed_exchange(row):
            t0 = time.perf_counter()
            exchange(row)
            spent["(exchange: get/set of all FMUs)"] = spent.get(
                "(exchange: get/set of all FMUs)", 0.0) + time.perf_counter() - t0
        m._exchange = timed_exchange
    t0 = time.perf_counter()
    res = m.run()
    wall = time.perf_counter() - t0
    if res.error:
        raise SystemExit(f"the run failed: {res.error}")
    return wall, spent, s.n_steps


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stop-time", type=float, default=550.0)
    ap.add_argument("--fmus", default=str(ROOT / "fmus"))
    ap.add_argument("--json", help="also write the numbers to this file")
    args = ap.parse_args()
    s = load_scenario(ROOT / "scenarios" / "sma-position-control.toml", stop_time=args.stop_time)
    wall, _, n = timed_run(s, args.fmus, split=False)
    _, spent, _ = timed_run(s, args.fmus, split=True)
    report = {"simulated_s": s.stop_time, "steps": n, "wall_s": wall,
              "real_time_factor": s.stop_time / wall, "us_per_step": 1e6 * wall / n,
              "us_per_step_by_fmu": {k: 1e6 * v / n for k, v in
                                     sorted(spent.items(), key=lambda kv: -kv[1])}}
    print(f"{s.name}: {s.stop_time:g} s simulated ({n} steps at {s.step * 1e3:g} ms) in "
          f"{wall:.1f} s: real-time factor {report['real_time_factor']:.2f} "
          f"({report['us_per_step']:.1f} us per communication step)")
    for k, v in report["us_per_step_by_fmu"].items():
        print(f"  {k:34s} {v:7.1f} us/step")
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
