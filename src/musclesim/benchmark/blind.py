"""`musclesim benchmark-diagnosis`: the diagnosis checked blind on virtual hardware.

Each case is a measured data set made by running one of the SMA benches with hidden changes:

- ``effect``: one library effect at a random magnitude (ranges from the model reference,
  `MAGNITUDES`);
- ``decoy``: an effect with a look-alike in the library (`DECOYS`: both act at high
  temperatures, or both make the reading trail the model);
- ``none``: no change at all;
- ``outside``: a change neither the library nor the calibration holds (`OUTSIDE`: a wire that
  slips in its clamp, a strain gauge whose offset drifts);

all with nuisances: thermocouple noise and quantisation inside the loop, strain-gauge noise and
quantisation, and an acquisition latency of the strain gauge of 0 or 1 sample behind the
controller's log. A quarter of the effect cases (drawn from a stream of their own) run on a load
bench instead: the magnet bench hiding an electromagnet force nonlinearity or a load-cell lag, or
the weight bench (§capstan-multiplier's 150 g weight lifted by fast heating pulses) hiding the
weight's inertia; with laser and load-cell noise and quantisation (the library's "laser noise" as
the nuisance it is: noise raises the floor, no fit of it can shrink a gap). Another quarter (a third
stream; it wins over the load-bench draw) runs on the pneumatic crawler climbing 7.5 deg (12 s of
crawler-gait-incline, the controllers' duties replayed, pressure sensors and the blocks' video
positions observed, both with noise and quantisation) and hides one of the crawler's effects, one
magnitude for every instance of its component. Cases are written without labels (data.csv +
manifest.toml); the key is hashed into key.sha256 before any diagnosis runs and written to key.json
after. Scores (scores.json): top-1 accuracy over effect and decoy cases, the median ratio of our
held-out shrinkage (the model with every measured signal replayed) to the oracle's (the true effect
at its true values), the false-alarm rate over ``none`` cases (a verdict naming an effect) and the
``unexplained`` rate over ``outside`` cases.

With ``bench="independent"`` the cases run instead on an SMA bench written apart from the library
(`musclesim.benchmark.benches.sma`, cases from `musclesim.benchmark.plan`), and on
request on a crawler written apart too (`musclesim.benchmark.benches.crawler`), whose
conditions are drawn around the model's; its scores go under "independent" in scores.json, next
to the own bench's (see `score` for what counts there).

With ``bench="family"`` (or ``"crawler-family"``) the cases are drawn from the SMA (crawler)
family of bench forms (`musclesim.benchmark.family`, `musclesim.benchmark.family_crawler`), a
cause of each kind in equal shares, and scored by the calibrated sets in their reports
(`musclesim.benchmark.calibrate.score`: coverage per cause, set sizes, false alarms, the gate),
under the family's name in scores.json; with `calibration` a file, the cases are the pool that
calibration is then built from (`musclesim.benchmark.calibrate.build`).

A run that stopped (a pool takes hours) goes on with ``resume``: the same cases (the sealed
key's hash must match) are kept where their report is written, the rest recorded and diagnosed.
"""
from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from musclesim.batch import serial_map
from musclesim.benchmark import calibrate
from musclesim.benchmark import plan as independent_plan
from musclesim.benchmark.cases import BENCHES, DECOYS, MAGNITUDES, OUTSIDE, plan, plan_multiplier
from musclesim.benchmark.recording import (bench_scenario, make_case, record, record_many,
                                           write_case)
from musclesim.benchmark.scoring import oracle, reliability, score, weighed, write_scores
from musclesim.cosim import replace_file
from musclesim.diagnosis import diagnose, load_dataset
from musclesim.errors import UserError

# the names of the benchmark's parts, kept where they were before the split (``blind.plan``, ...)
__all__ = ["run", "each", "plan", "plan_multiplier", "record", "bench_scenario", "make_case",
           "score", "weighed", "reliability", "BENCHES", "DECOYS", "MAGNITUDES", "OUTSIDE"]


def _record(args: tuple[list[tuple[dict[str, Any], Any]], Any]) -> list[tuple]:
    """The recordings of the own bench's (case, scenario) pairs of `args` (pairs, FMU folder),
    in one compiled pass where they fuse (`record_many`)."""
    pairs, fmu_dir = args
    return record_many(pairs, fmu_dir)


def _by_bench(cases: Sequence[dict[str, Any]], todo: Sequence[int], width: int
              ) -> list[list[int]]:
    """The cases `todo` (indices into `cases`) in runs of one bench each, about two per task the
    map runs at once (`width`), so that each run is one compiled pass and the map stays busy."""
    benches: dict[str, list[int]] = {}
    for i in todo:
        benches.setdefault(cases[i]["bench"], []).append(i)
    size = max(1, -(-len(todo) // (2 * width)))
    return [same[k:k + size] for same in benches.values() for k in range(0, len(same), size)]


def _diagnose(args: tuple[Any, Any]) -> dict[str, Any]:
    """The report.json document of the diagnosis of `args` (data set, FMU folder), or an
    error's."""
    ds, fmu_dir = args
    try:
        return diagnose(ds, fmu_dir).to_json()
    except UserError as exc:
        return {"verdict": "error", "error": str(exc)}


def run(count: int, seed: int, out: str | Path, fmu_dir: str | Path = "fmus",
        scenarios_dir: str | Path = "scenarios", pmap: Any = None,
        progress: Callable[[str], None] | None = None, bench: str = "own",
        duration: float | None = None, multiplier: int = 0, crawler: int = 0,
        calibration: str | Path | None = None, resume: bool = False) -> dict[str, Any]:
    """Make `count` cases from `seed` into `out`, diagnose them blind, score; return the scores.

    `multiplier`: that many extra cases on the capstan multiplier's bench (`plan_multiplier`;
    own bench only), after the `count` cases, which stay as they are without them; `crawler`
    likewise on the independent crawler bench (`independent_plan.plan_crawler`; independent
    bench only). The scores then also come per bench (``by_bench``).

    `bench` "own" records on the library's FMUs (in `fmu_dir`; its scenarios in
    `scenarios_dir`) with hidden effects switched on (cases in ``out/cases``, scores at the top
    of ``out/scores.json``); "independent" on `musclesim.benchmark.benches.sma`'s bench,
    `duration` seconds each (default `independent_plan.DURATION`; cases, key in
    ``out/independent``, scores under the key "independent" of ``out/scores.json``). Each keeps
    the other's scores in the file. "family" and "crawler-family" draw their cases from a
    family of bench forms (`musclesim.benchmark.calibrate.FAMILIES`; in ``out/<bench>``, scores
    under its name: `musclesim.benchmark.calibrate.score`); with `calibration` a file path, the
    calibration built from those cases (`musclesim.benchmark.calibrate.build`) is written there.
    With `resume`, `out` holds a run of the same cases that stopped: the cases whose report is
    written are kept. The cases run on `pmap` (a map such as `musclesim.batch.serial_map`, the
    default, or a Dask map); `progress` is told each step.
    """
    benches = ("own", "independent", *calibrate.FAMILIES)
    if bench not in benches:
        raise UserError(f"no bench {bench!r} for the blind benchmark ({', '.join(benches)})")
    if calibration is not None and bench not in calibrate.FAMILIES:
        raise UserError("a calibration is built from a family's cases only (--bench "
                        f"{' or '.join(calibrate.FAMILIES)})")
    if calibration is not None and not Path(calibration).resolve().parent.is_dir():
        raise UserError(f"--calibrate {calibration}: its folder does not exist")
    if multiplier and bench != "own":
        raise UserError("multiplier cases run on the own bench only (--bench own)")
    if crawler and bench != "independent":
        raise UserError("independent crawler cases run on the independent bench only "
                        "(--bench independent)")
    pmap = pmap or serial_map
    say = progress or (lambda text: None)
    top = Path(out)
    out = top / bench if bench != "own" else top
    out.mkdir(parents=True, exist_ok=True)
    # the workers get the FMUs as bytes and every case as data: they need none of this
    # process's files, and the data sets and reports are written here
    fmus = pmap.ship_fmus(fmu_dir) if hasattr(pmap, "ship_fmus") else fmu_dir
    recorded: tuple[Callable[[Any], tuple], list[Any]]
    score_gap: Callable[[Any], dict[str, Any]]
    if bench == "own":
        cases = plan(count, seed) + plan_multiplier(multiplier, seed)
        scenarios = [bench_scenario(c, scenarios_dir) for c in cases]
        score_gap = oracle
    elif bench in calibrate.FAMILIES:
        fam = calibrate.FAMILIES[bench]
        cases = fam.plan(count, seed, duration or fam.duration)
        recorded = (fam.record, [(c, scenarios_dir, fmus) for c in cases])
    else:
        cases = (independent_plan.plan(count, seed, DECOYS, duration or independent_plan.DURATION)
                 + independent_plan.plan_crawler(crawler, seed))
        recorded = (independent_plan.record, cases)
        score_gap = independent_plan.oracle
    dirs = [out / "cases" / c["case"] for c in cases]
    key = json.dumps({"seed": seed, "cases": cases}, indent=1, sort_keys=True) + "\n"
    digest = hashlib.sha256(key.encode()).hexdigest()
    todo = list(range(len(cases)))
    if not resume:  # a new run: nothing a previous run left in `out` may pass for this one's
        for stale in (out / "key.sha256", out / "key.json", *(d / "report.json" for d in dirs)):
            stale.unlink(missing_ok=True)
    else:
        sealed = out / "key.sha256"
        if not sealed.is_file() or sealed.read_text().split()[:1] != [digest]:
            raise UserError(f"--resume: {out} holds no run of these cases (none at all, or "
                            "another --seed, --cases, --bench or --duration)")
        todo = [i for i, d in enumerate(dirs) if not (d / "report.json").is_file()]
        say(f"resuming: {len(cases) - len(todo)} of {len(cases)} cases diagnosed before")
    say(f"recording {len(todo)} cases on the {bench} virtual hardware")
    if bench == "own":  # a bench's cases in one compiled pass
        runs = _by_bench(cases, todo, pmap.width() if hasattr(pmap, "width") else 1)
        order = [i for part in runs for i in part]
        recordings = [r for part in pmap(_record, [([(cases[i], scenarios[i]) for i in part],
                                                    fmus) for part in runs]) for r in part]
    else:
        fn, items = recorded
        order, recordings = list(todo), pmap(fn, [items[i] for i in todo])
    for i, (time, cols, *stated) in zip(order, recordings):
        write_case(cases[i], dirs[i], time, cols, (stated or [None])[0], scenarios_dir)
    # sealed: `sha256sum -c key.sha256` checks key.json once it is written, after the diagnosis
    (out / "key.sha256").write_text(digest + "  key.json\n")
    say("diagnosing blind")
    sets = [load_dataset(d, fmu_dir=fmu_dir).loaded() for d in dirs]
    count_done = [len(cases) - len(todo)]

    def written(j: int, report: dict[str, Any]) -> None:  # each report as its case ends
        replace_file(dirs[todo[j]] / "report.json",
                     json.dumps(report, indent=1, default=float) + "\n")
        count_done[0] += 1
        say(f"{cases[todo[j]]['case']} diagnosed ({count_done[0]} of {len(cases)})")
    each(pmap, _diagnose, [(sets[i], fmus) for i in todo], written)
    reports = [json.loads((d / "report.json").read_text()) for d in dirs]
    (out / "key.json").write_text(key)
    if bench in calibrate.FAMILIES:
        say("scoring the calibrated sets against the key")
        scores = calibrate.score(cases, reports, fam=fam)
        write_scores(top / "scores.json", scores, bench)
        if calibration is not None:
            say(f"building the calibration from the {len(cases)} cases")
            calibrate.write(calibration, calibrate.build(out, fam))
        return scores
    say("scoring against the key and the oracle")
    gaps = pmap(score_gap, [(c, ds, r, fmus) for c, ds, r in zip(cases, sets, reports)])
    scores = score(cases, reports, gaps)
    write_scores(top / "scores.json", scores, bench)
    return scores


def each(pmap: Any, fn: Callable[[Any], Any], items: Sequence[Any],
         done: Callable[[int, Any], None]) -> list[Any]:
    """[`fn`(item) for item in `items`] on `pmap`, calling `done`(index, result) as each ends:
    several at once where the map takes calls from several threads (a Dask map), one after the
    other otherwise."""
    from concurrent.futures import ThreadPoolExecutor

    def one(i: int) -> Any:
        result = pmap(fn, [items[i]])[0]
        done(i, result)
        return result
    if not getattr(pmap, "concurrent", False):
        return [one(i) for i in range(len(items))]
    with ThreadPoolExecutor(max_workers=max(1, pmap.width())) as pool:
        return list(pool.map(one, range(len(items))))
