"""Real-time factor of the SMA position-control scenario (§position-control) on both hosts, and
where a step's time goes.

    .venv/bin/python benchmarks/bench_position.py [--stop-time 550] [--every 25] [--fmus DIR]
        [--json FILE]

First the master as `musclesim run` uses it (the direct host), then with fmpy as the host, each
timed as a whole in this process -> real-time factors (simulated time / wall time; above 1 =
faster than real time) and their ratio. Then the same on the direct host with the reference chain
(the two profiles and the Preisach inverse) stepping every `--every` points (multi-rate,
docs/user/scenarios.md): its real-time factor and how far the wire's strain moves from the
single-rate run (a choice a user makes, not the study's scenario). Then the monolithic model of the
same equations, compiled (components/sma/monolithic.py: the limit), from the scenario's state after
initialization (its loading and initialization untimed, ours timed whole), its rows checked equal
to ours bit for bit. Then a profiled run of the
direct host: the time spent in each component's `advance` and `evaluate`, and in the master's
loop around them, stepped per call (the profiler's overhead inflates all of them; the split is
what it is for). Every run is timed after an untimed one of the same scenario (the compiled code
loaded, the hysteresis tables read once per process). Goals (issue 56): at least 50x faster than
real time, stepping every point; ours (the direct host) within 2x the monolithic model's time.
Run it on a quiet machine; nothing here is part of the test suite.
"""
import argparse
import cProfile
import dataclasses
import json
import pstats
import time
from pathlib import Path

import numpy as np

from musclesim.components.sma.monolithic import RECORD, simulate_position
from musclesim.cosim import Master, Signal, check_fresh, load_scenario

ROOT = Path(__file__).resolve().parents[1]
GOAL = 50.0  # real-time factor (issue 56: stepping every point, no multi-rate)
GOAL_VS_COMPILED = 2.0  # ours (direct host) at most this many times the monolithic model's time
SLOW = ("strain", "loading", "inverse")  # the reference chain: profiles and the inverse

STRAIN = Signal("wire", "strain")  # the signal the runs are compared on


def timed_run(s, fmu_dir, host):
    """(wall seconds, results) of one run on `host`."""
    t0 = time.perf_counter()
    res = Master(s, fmu_dir, host=host).run()
    wall = time.perf_counter() - t0
    if res.error:
        raise SystemExit(f"the run failed: {res.error}")
    return wall, res


def timed_monolithic(s, fmu_dir):
    """(wall seconds of the monolithic model's run, whether its rows are ours bit for bit),
    started from the state our run of `s` reached at initialization."""
    m = Master(s, fmu_dir)
    with m.session(None) as run:
        parts = m.kernels()
        run.error = m.steps(run)
    res = run.results
    if res is None or res.error:
        raise SystemExit(f"the run failed: {res.error if res else 'no results'}")
    t0 = time.perf_counter()
    times, rows = simulate_position(parts, s.step, s.n_steps)
    wall = time.perf_counter() - t0
    same = np.array_equal(times, res.time) and all(
        np.array_equal(rows[:, j], res[Signal.parse(name)]) for j, name in enumerate(RECORD))
    return wall, same


def multirate(s, every):
    """`s` with the reference chain stepping every `every` points."""
    return dataclasses.replace(s, instances={
        n: dataclasses.replace(i, every=every) if n in SLOW else i
        for n, i in s.instances.items()})


def split(s, fmu_dir):
    """{component function: seconds (cumulative, under the profiler)} of one direct run stepped
    per call (`fuse=False`: a fused run is one compiled call the profiler cannot look into)."""
    prof = cProfile.Profile()
    prof.runcall(Master(s, fmu_dir, fuse=False).run)
    stats = pstats.Stats(prof).stats
    return {f"{Path(file).parent.name}/{Path(file).name}:{fn}": cum
            for (file, _, fn), (_, _, _, cum, _) in stats.items()
            if "components" in file and fn in ("advance", "evaluate")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stop-time", type=float, default=550.0)
    ap.add_argument("--fmus", default=str(ROOT / "fmus"))
    ap.add_argument("--every", type=int, default=25,
                    help="the reference chain's steps at once in the multi-rate run (25: 10 ms)")
    ap.add_argument("--json", help="also write the numbers to this file")
    args = ap.parse_args()
    check_fresh(args.fmus)
    s = load_scenario(ROOT / "scenarios" / "sma-position-control.toml", stop_time=args.stop_time)
    timed_run(s, args.fmus, "direct")  # compiled, or loaded from the cache, before timing
    timed_run(multirate(s, args.every), args.fmus, "direct")
    timed_monolithic(s, args.fmus)  # compiled, or loaded from the cache
    wall_mono, same = timed_monolithic(s, args.fmus)
    runs = {host: timed_run(s, args.fmus, host) for host in ("direct", "fmpy")}
    wall_m, res_m = timed_run(multirate(s, args.every), args.fmus, "direct")
    walls = {host: wall for host, (wall, _) in runs.items()}
    rtf = {host: s.stop_time / wall for host, wall in walls.items()}
    strain = runs["direct"][1][STRAIN]
    spent = split(s, args.fmus)
    report = {"simulated_s": s.stop_time, "steps": s.n_steps, "wall_s": walls,
              "real_time_factor": rtf, "fmpy_over_direct": walls["fmpy"] / walls["direct"],
              "monolithic_compiled_s": wall_mono, "monolithic_bits_equal": same,
              "ours_over_monolithic_compiled": walls["direct"] / wall_mono,
              "us_per_step": {h: 1e6 * w / s.n_steps for h, w in walls.items()},
              "multirate": {"every": args.every, "instances": SLOW, "wall_s": wall_m,
                            "real_time_factor": s.stop_time / wall_m,
                            "max_strain_change": float(np.abs(res_m[STRAIN] - strain).max()),
                            "strain_range": float(np.ptp(strain))},
              "profiled_us_per_step": {k: 1e6 * v / s.n_steps for k, v in
                                       sorted(spent.items(), key=lambda kv: -kv[1])}}
    print(f"{s.name}: {s.stop_time:g} s simulated ({s.n_steps} steps at {s.step * 1e3:g} ms)")
    for host in walls:
        print(f"  {host:6s}: {walls[host]:.1f} s, real-time factor {rtf[host]:.2f} "
              f"({report['us_per_step'][host]:.1f} us per communication step)")
    print(f"  fmpy / direct: {report['fmpy_over_direct']:.2f}; goal >= {GOAL:g}x real time: "
          f"{'met' if rtf['direct'] >= GOAL else 'MISSED'}")
    ratio = report["ours_over_monolithic_compiled"]
    print(f"  monolithic compiled: {wall_mono:.2f} s (its rows ours bit for bit: {same}); ours "
          f"{ratio:.2f}x its time (goal <= {GOAL_VS_COMPILED:g}x: "
          f"{'met' if ratio <= GOAL_VS_COMPILED else 'MISSED'})")
    m = report["multirate"]
    print(f"  direct, {', '.join(SLOW)} every {m['every']} points: {m['wall_s']:.1f} s, real-time "
          f"factor {m['real_time_factor']:.2f}; wire strain moves by at most "
          f"{m['max_strain_change']:.2e} (its range {m['strain_range']:.2e})")
    print("  profiled, unfused, per communication step:")
    for k, v in report["profiled_us_per_step"].items():
        print(f"    {k:48s} {v:7.1f} us")
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
