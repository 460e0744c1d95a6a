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
"""
import hashlib
import json
import math
import statistics
from dataclasses import replace
from pathlib import Path

import numpy as np

from musclesim.batch import serial_map
from musclesim.benchmark import plan as independent_plan
from musclesim.cosim import Master, load_scenario, replace_file
from musclesim.diagnosis import (CALIBRATION_ONLY, HELD_OUT, Failed, Problem, diagnose, gap,
                                 load_dataset, residuals, simulate_unit, with_values,
                                 write_data_set)
from musclesim.errors import UserError

# the benches: scenario, replayed inputs, observed outputs, the effects that can hide in them
BENCHES = {
    "tracking": ("sma-bench-tracking", ["reference.y"],
                 ["pid.y", "thermocouple.T_meas", "wire.strain"],
                 ["thermocouple lag", "thermocouple bias", "latent heat", "convection change",
                  "training drift"]),
    "stress": ("sma-bench-stress", ["wire.u", "wire.flange.f"],
               ["thermocouple.T_meas", "wire.strain"],
               ["stress dependence ignored", "thermocouple lag", "latent heat"]),
    "magnet": ("sma-bench-magnet", ["wire.u", "magnet.duty"],
               ["loadcell.f_meas", "thermocouple.T_meas", "laser.s_meas"],
               ["electromagnet force nonlinearity", "load-cell lag"]),
    # §capstan-multiplier's 150 g weight lifted by fast heating pulses, the laser on the weight
    "weight": ("sma-dead-weight", ["wire.u"], ["laser.s_meas"], ["load inertia"]),
    # the pneumatic crawler climbing 7.5 deg (where bending shows): the controllers' logged
    # duties replayed, the pressure sensors and the blocks' positions from video observed
    "crawler": ("crawler-gait-incline", ["act1.duty", "actc.duty", "act2.duty"],
                ["sensor1.p_meas", "sensorc.p_meas", "sensor2.p_meas", "body.flange_a.s",
                 "body.flange_b.s"],
                ["valve delay", "supply-pressure drop", "chamber leakage",
                 "pressure-dependent stiffness", "actuator bending on an incline",
                 "friction decay"]),
    # §multiplier-experiments's capstan multiplier under the 150 g weight, bang-bang heated: the
    # relay's voltage replayed, the middle segment's thermocouple and the laser on the weight
    # observed (only in the extra multiplier cases, `plan_multiplier`)
    "multiplier": ("sma-bench-multiplier", ["mult.u"], ["thermocouple.T_meas", "laser.s_meas"],
                   ["capstan friction", "composition difference", "load inertia"]),
}
STOP_TIME = {"crawler": 12.0,  # s: the first stride and three more (the scenario runs 30 s)
             "weight": 6.0,  # s: two lifts, the second in the held-out part
             "multiplier": 6.0}  # s: the first lift and about ten relay cycles
LOAD_SHARE = 0.25  # of the effect cases move to a load bench, magnet or weight, with one of its
                   # effects (drawn from their own stream)
LOAD_BENCHES = ("magnet", "weight")
CRAWLER_SHARE = 0.25  # ... and, drawn from a third stream, to the crawler bench
# Not in the tracking bench's pool, so without a magnitude here: clamp heat loss (cold ends), the
# look-alike of the decoy pair below; the independent bench hides it (`independent_plan`). hidden
# magnitudes: (instance, parameter, low, high), drawn uniformly (§sma-wire, §drift, §sma-material)
MAGNITUDES = {
    "thermocouple lag": [("thermocouple", "tau", 0.1, 0.6)],
    "thermocouple bias": [("thermocouple", "bias", 1.5, 5.0)],  # sign drawn too
    "latent heat": [("wire", "latent_heat", 12e3, 24e3)],
    "convection change": [("wire", "h_exponent", 0.06, 0.15)],
    "training drift": [("wire", "drift_amplitude", 0.1, 0.2), ("wire", "drift_shift", 5.0, 10.0)],
    "stress dependence ignored": [("wire", "stress_blend", 0.5, 1.0)],
    "electromagnet force nonlinearity": [("magnet", "nonlinearity", 0.2, 0.5)],
    # a heavily filtered cell: lags of 1-2 samples (20-40 ms) are latency at this data rate
    "load-cell lag": [("loadcell", "tau", 0.1, 0.3)],
    "load inertia": [("weight", "inertia", 0.3, 1.0)],
    # one draw for several instances: the three valves, pumps and chambers are alike
    "valve delay": [(("act1", "actc", "act2"), "t_open_delay", 0.005, 0.02),
                    (("act1", "actc", "act2"), "t_close_delay", 0.005, 0.02)],
    "supply-pressure drop": [(("act1", "actc", "act2"), "supply_drop", 0.2, 0.5)],
    "chamber leakage": [(("act1", "actc", "act2"), "C_leak", 2e-11, 5e-11)],
    "pressure-dependent stiffness": [("body", "k_slope", 0.015, 0.04)],
    "actuator bending on an incline": [(("friction1", "friction2"), "bending", 1.5, 4.0)],
    "friction decay": [(("friction1", "friction2"), "mu_decay", 0.01, 0.02)],
    # a groove worn or dirty: 2-4 times §capstan-multiplier's 0.0237 +/- 0.0037
    "capstan friction": [("mult", "mu_f", 0.05, 0.1)],
    # transformation temperatures of NiTi move ~10 K per 0.1 at.% Ni; a few K between batches
    "composition difference": [("mult", "composition_shift", 3.0, 8.0)],  # sign drawn too
}
SIGNED = {"thermocouple bias", "training drift", "electromagnet force nonlinearity",
          "pressure-dependent stiffness", "composition difference"}
MULTIPLIER_NONE_SHARE = 0.2  # of the multiplier cases hide nothing (false alarms there)
# (hidden effect, its decoy in the library): both act at high temperatures, or both make the
# measured temperature trail the wire's model
DECOYS = [("convection change", "clamp heat loss"), ("thermocouple lag", "latent heat"),
          ("latent heat", "thermocouple lag")]
# Changes neither in the effect library nor in the calibration (a warmer room or a strain gauge's
# gain error are: the ambient and the strain scale are calibrated), applied to the recorded
# strain: the wire slips in its clamp 2-4 times (the reading steps down by this much each time),
# or the gauge's offset drifts linearly by this much over the run (2.5-5 % of the strain's
# range, beyond what its noise hides)
OUTSIDE = {
    "clamp slip": (3e-4, 8e-4),
    "gauge drift": (1e-3, 2e-3),
}
# nuisances (the same for every case; magnitudes of a bench like §sma-bench's)
TC_NOISE, TC_QUANTUM = 0.08, 0.05  # K
STRAIN_NOISE, STRAIN_QUANTUM = 2e-5, 1e-5
LASER_NOISE, LASER_QUANTUM = 2e-6, 1e-6  # m (the laser-noise effect of the library as nuisance)
LOADCELL_NOISE, LOADCELL_QUANTUM = 2e-3, 1e-3  # N
PRESSURE_NOISE, PRESSURE_QUANTUM = 30.0, 10.0  # Pa
VIDEO_NOISE, VIDEO_QUANTUM = 2e-4, 1e-4  # m: block edges tracked on video
VIDEO = ("body.flange_a.s", "body.flange_b.s")  # the columns the video gives
# (sensor instance, noise, quantum, modulus of the case's seed that seeds it)
NUISANCES = [("thermocouple", TC_NOISE, TC_QUANTUM, 100000),
             ("laser", LASER_NOISE, LASER_QUANTUM, 100001),
             ("loadcell", LOADCELL_NOISE, LOADCELL_QUANTUM, 100003),
             ("sensor1", PRESSURE_NOISE, PRESSURE_QUANTUM, 100019),
             ("sensorc", PRESSURE_NOISE, PRESSURE_QUANTUM, 100043),
             ("sensor2", PRESSURE_NOISE, PRESSURE_QUANTUM, 100049)]
HELD_OUT_FRACTION = 0.35


def plan(count, seed):
    """The cases' hidden truths: a list of dicts (kind, bench, effect, values, latency, ...)."""
    rng = np.random.default_rng(seed)
    # their own streams, so that moving a case to another bench changes no other case
    load_rng = np.random.default_rng([seed, 7])
    crawler_rng = np.random.default_rng([seed, 11])
    n_none = max(1, round(0.15 * count))
    n_out = max(1, round(0.15 * count))
    n_decoy = max(1, round(0.15 * count))
    kinds = (["none"] * n_none + ["outside"] * n_out + ["decoy"] * n_decoy
             + ["effect"] * (count - n_none - n_out - n_decoy))[:count]
    rng.shuffle(kinds)
    cases = []
    for i, kind in enumerate(kinds):
        bench = "stress" if kind == "effect" and rng.random() < 0.25 else "tracking"
        case = {"case": f"case-{i:03d}", "kind": kind, "bench": bench, "effect": None,
                "values": {}, "latency_samples": int(rng.integers(0, 2)), "seed": int(
                    rng.integers(0, 2**31))}
        if kind in ("effect", "decoy"):
            pool = BENCHES[bench][3] if kind == "effect" else [d[0] for d in DECOYS]
            effect = pool[rng.integers(len(pool))]
            case["effect"] = effect
            case["values"] = _draw(effect, rng)
        if kind == "effect":  # moved to a load bench, then (the later draw wins) the crawler
            for benches, share, stream in ((LOAD_BENCHES, LOAD_SHARE, load_rng),
                                           (("crawler",), CRAWLER_SHARE, crawler_rng)):
                if stream.random() < share:
                    pool = [(b, e) for b in benches for e in BENCHES[b][3]]
                    bench, effect = pool[stream.integers(len(pool))]
                    case.update(bench=bench, effect=effect, values=_draw(effect, stream))
        elif kind == "outside":
            name = list(OUTSIDE)[rng.integers(len(OUTSIDE))]
            case["effect"] = name
            if name == "clamp slip":  # (fraction of the run, strain lost) per slip
                case["slips"] = [[float(rng.uniform(0.1, 0.95)), float(rng.uniform(
                    *OUTSIDE[name]))] for _ in range(int(rng.integers(2, 5)))]
            else:
                case["strain_drift"] = float(rng.choice([-1, 1]) * rng.uniform(*OUTSIDE[name]))
        cases.append(case)
    return cases


def plan_multiplier(count, seed):
    """`count` extra cases on the multiplier bench, from a stream of their own (so the cases of
    `plan` stay the same): a library effect of the bench at a random magnitude, or (a share
    `MULTIPLIER_NONE_SHARE`) none; ids ``case-m000``, ...

    Examples
    --------
    >>> [c["bench"] for c in plan_multiplier(2, 1)]
    ['multiplier', 'multiplier']
    """
    rng = np.random.default_rng([seed, 13])
    effects_ = BENCHES["multiplier"][3]
    cases = []
    for i in range(count):
        kind = "none" if rng.random() < MULTIPLIER_NONE_SHARE else "effect"
        case = {"case": f"case-m{i:03d}", "kind": kind, "bench": "multiplier", "effect": None,
                "values": {}, "latency_samples": int(rng.integers(0, 2)),
                "seed": int(rng.integers(0, 2**31))}
        if kind == "effect":
            effect = effects_[rng.integers(len(effects_))]
            case.update(effect=effect, values=_draw(effect, rng))
        cases.append(case)
    return cases


def _draw(effect, rng):
    """{"instance.parameter": value} of `effect` at a random magnitude (and sign if signed)."""
    sign = -1.0 if effect in SIGNED and rng.random() < 0.5 else 1.0
    values = {}
    for inst, par, lo, hi in MAGNITUDES[effect]:
        v = float(sign * rng.uniform(lo, hi))
        values.update({f"{i}.{par}": v for i in ((inst,) if isinstance(inst, str) else inst)})
    return values


def _scenario_path(bench, scenarios_dir):
    return Path(scenarios_dir) / f"{BENCHES[bench][0]}.toml"


def bench_scenario(case, scenarios_dir):
    """The scenario of `case`'s bench with its hidden values set (what `record` runs)."""
    sets = [f"{k}={v!r}" for k, v in case["values"].items()]
    return load_scenario(_scenario_path(case["bench"], scenarios_dir), sets,
                         STOP_TIME.get(case["bench"]))


def record(case, s, fmu_dir):
    """Run the virtual hardware of `case` on its bench's scenario `s` (`bench_scenario`): (time,
    {column: values}) as the bench records them."""
    name, inputs, outputs, _ = BENCHES[case["bench"]]
    # the nuisances on the sensors this bench has (with_values skips the others)
    s = with_values(s, {(inst, par): v for inst, noise, quantum, modulus in NUISANCES
                        for par, v in (("noise_std", noise), ("quantum", quantum),
                                       ("seed", case["seed"] % modulus))})
    s = replace(s, record=tuple(inputs + outputs), metrics={}, plots=())
    res = Master(s, fmu_dir).run()
    if res.error:
        raise UserError(f"{case['case']}: the virtual hardware failed: {res.error}")
    rng = np.random.default_rng(case["seed"])
    cols = {c: res[c].copy() for c in inputs + outputs}
    if "wire.strain" in cols:  # a strain gauge: its noise and quantisation (the laser's in-FMU)
        strain = cols["wire.strain"] + STRAIN_NOISE * rng.standard_normal(
            len(res.time)) + _outside_strain(case, res.time)
        cols["wire.strain"] = STRAIN_QUANTUM * np.round(strain / STRAIN_QUANTUM)
    for c in VIDEO:  # noise, pixel quantisation
        if c in cols:
            x = cols[c] + VIDEO_NOISE * rng.standard_normal(len(res.time))
            cols[c] = VIDEO_QUANTUM * np.round(x / VIDEO_QUANTUM)
    lag = case["latency_samples"]
    # the gauge's (or laser's, or the video's) own acquisition lags the controller's log
    for c in ("wire.strain", "laser.s_meas", *VIDEO) if lag else ():
        if c in cols:
            cols[c] = np.concatenate([np.full(lag, cols[c][0]), cols[c][:-lag]])
    return res.time, cols


def _outside_strain(case, t):
    """What an outside change adds to the strain reading at times `t` (zeros without one)."""
    span = t[-1] - t[0]
    add = case.get("strain_drift", 0.0) * (t - t[0]) / span
    for at, lost in case.get("slips", ()):
        add = add - lost * (t >= t[0] + at * span)
    return add


def _record(args):
    case, s, fmu_dir = args
    return record(case, s, fmu_dir)


def _diagnose(args):
    ds, fmu_dir = args
    try:
        return diagnose(ds, fmu_dir)
    except UserError as exc:
        return {"verdict": "error", "error": str(exc)}


def _oracle(args):
    """Held-out gap of the model with every measured signal replayed (the report's section 4):
    nominal and with our selected effects' values, as the report has them, and with the true
    values (the oracle), simulated here."""
    case, ds, report, fmu_dir = args
    problem = Problem(ds, fmu_dir)
    whole = problem.replayed()

    def heldout(values):
        try:
            sims = simulate_unit(whole, values, fmu_dir)
        except Failed:
            return math.inf
        return gap(whole, residuals(whole, sims), HELD_OUT)

    truth = {tuple(k.split(".", 1)): v for k, v in case["values"].items()}
    ours = report.get("shrinkage", {}).get("all")
    before = ours["before"] if ours else heldout({})  # no report section 4: the case failed
    return {"before": before, "oracle": heldout(truth), "ours": ours["after"] if ours else before}


def run(count, seed, out, fmu_dir="fmus", scenarios_dir="scenarios", pmap=None, progress=None,
        bench="own", duration=None, multiplier=0, crawler=0):
    """Make `count` cases from `seed` into `out`, diagnose them blind, score; return the scores.

    ``multiplier``: that many extra cases on the capstan multiplier's bench (`plan_multiplier`;
    own bench only), after the `count` cases, which stay as they are without them; ``crawler``
    likewise on the independent crawler bench (`independent_plan.plan_crawler`; independent
    bench only). The scores then also come per bench (``by_bench``).

    `bench` "own" records on the library's FMUs with hidden effects switched on (cases in
    ``out/cases``, scores at the top of ``out/scores.json``); "independent" on
    `musclesim.benchmark.benches.sma`'s bench, `duration` seconds each (default
    `independent_plan.DURATION`; cases, key in ``out/independent``, scores under the key
    "independent" of ``out/scores.json``). Each keeps the other's scores in the file.
    """
    if bench not in ("own", "independent"):
        raise UserError(f"no bench {bench!r} for the blind benchmark (own or independent)")
    if multiplier and bench != "own":
        raise UserError("multiplier cases run on the own bench only (--bench own)")
    if crawler and bench != "independent":
        raise UserError("independent crawler cases run on the independent bench only "
                        "(--bench independent)")
    pmap = pmap or serial_map
    say = progress or (lambda text: None)
    top = Path(out)
    out = top / "independent" if bench == "independent" else top
    out.mkdir(parents=True, exist_ok=True)
    # the workers get the FMUs as bytes and every case as data: they need none of this
    # process's files, and the data sets and reports are written here
    fmus = pmap.ship_fmus(fmu_dir) if hasattr(pmap, "ship_fmus") else fmu_dir
    if bench == "own":
        cases = plan(count, seed) + plan_multiplier(multiplier, seed)
        recorded = (_record, [(c, bench_scenario(c, scenarios_dir), fmus) for c in cases])
        oracle = _oracle
    else:
        cases = (independent_plan.plan(count, seed, DECOYS, duration or independent_plan.DURATION)
                 + independent_plan.plan_crawler(crawler, seed))
        recorded = (independent_plan.record, cases)
        oracle = independent_plan.oracle
    say(f"recording {len(cases)} cases on the {bench} virtual hardware")
    dirs = [out / "cases" / c["case"] for c in cases]
    for case, folder, (time, cols, *stated) in zip(cases, dirs, pmap(*recorded)):
        _write_case(case, folder, time, cols, (stated or [None])[0], scenarios_dir)
    key = json.dumps({"seed": seed, "cases": cases}, indent=1, sort_keys=True) + "\n"
    # sealed: `sha256sum -c key.sha256` checks key.json once it is written, after the diagnosis
    (out / "key.sha256").write_text(hashlib.sha256(key.encode()).hexdigest() + "  key.json\n")
    say("diagnosing blind")
    sets = [load_dataset(d, fmu_dir=fmu_dir).loaded() for d in dirs]

    def written(i, report):  # each report as its case ends
        text = json.dumps(report, indent=1, default=float) + "\n"
        (dirs[i] / "report.json").write_text(text)
    reports = each(pmap, _diagnose, [(ds, fmus) for ds in sets], written)
    (out / "key.json").write_text(key)
    say("scoring against the key and the oracle")
    gaps = pmap(oracle, [(c, ds, r, fmus) for c, ds, r in zip(cases, sets, reports)])
    scores = score(cases, reports, gaps)
    _write_scores(top / "scores.json", scores, bench)
    return scores


def make_case(case, out, fmu_dir="fmus", scenarios_dir="scenarios"):
    """Record `case` on its bench and write its data set into ``out/cases/<case>``, here (what
    `run` does on its map); return that folder."""
    if case["bench"] in ("independent-crawler", independent_plan.BENCH):
        time, cols, stated = independent_plan.record(case)
    else:
        (time, cols), stated = record(case, bench_scenario(case, scenarios_dir), fmu_dir), None
    folder = Path(out) / "cases" / case["case"]
    _write_case(case, folder, time, cols, stated, scenarios_dir)
    return folder


def _write_case(case, folder, time, cols, stated, scenarios_dir):
    """Write `case`'s recording as a data set in `folder`, naming its model's scenario and the
    conditions the bench `stated`."""
    ip = independent_plan
    if case["bench"] == "independent-crawler":
        scenario, inputs, outputs = ip.CRAWLER_SCENARIO, ip.CRAWLER_INPUTS, ip.CRAWLER_OUTPUTS
        what = "the independent crawler bench"
    elif case["bench"] == ip.BENCH:
        scenario, inputs, outputs = ip.SCENARIO, ip.INPUTS, ip.OUTPUTS
        what = "the independent SMA bench"
    else:
        scenario, inputs, outputs, _ = BENCHES[case["bench"]]
        what = f"bench {scenario}"
    ref = str((Path(scenarios_dir) / f"{scenario}.toml").resolve())
    write_data_set(folder, time, cols, inputs, outputs, ref, f"blind case {case['case']} on {what}",
                   stated, held_out_fraction=HELD_OUT_FRACTION)


def each(pmap, fn, items, done):
    """[fn(item) for item in items] on `pmap`, calling done(index, result) as each ends: several
    at once where the map takes calls from several threads (a Dask map), one after the other
    otherwise."""
    from concurrent.futures import ThreadPoolExecutor

    def one(i):
        result = pmap(fn, [items[i]])[0]
        done(i, result)
        return result
    if not getattr(pmap, "concurrent", False):
        return [one(i) for i in range(len(items))]
    with ThreadPoolExecutor(max_workers=max(1, pmap.width())) as pool:
        return list(pool.map(one, range(len(items))))


def _write_scores(path, scores, bench):
    """scores.json: the own bench's scores at the top, the independent bench's under
    "independent"; a run replaces its own part and keeps the other's."""
    try:
        old = json.loads(path.read_text())
    except (OSError, ValueError):
        old = {}
    if bench == "own":
        new = {**scores, **({"independent": old["independent"]} if "independent" in old else {})}
    else:
        new = {**{k: v for k, v in old.items() if k != "independent"},
               "independent": {"bench": "independent", **scores}}
    replace_file(path, json.dumps(new, indent=1) + "\n")


BINS = 10  # reliability: the probabilities in tenths


def weighed(report):
    """{candidate: probability} and the credible set of a report: its evidence, or, where the
    diagnosis stopped before weighing (the model matched, or calibration alone did),
    calibration only, certain."""
    ev = report.get("evidence")
    if not ev:
        if report.get("verdict") in ("none", "recalibration"):
            return {CALIBRATION_ONLY: 1.0}, [CALIBRATION_ONLY]
        return {}, []
    return {c["name"]: c["probability"] for c in ev["candidates"]}, list(ev["set"])


def score(cases, reports, gaps):
    """The benchmark's scores and per-case table from the key, the reports and the gaps.

    The diagnosis answers with probabilities over candidate causes and a credible set
    (`weighed`). For an effect or decoy case the truth is its hidden effect; for a case without
    one, ``calibration only``. Scored per case: whether the truth is in the set, the set's size,
    the size-weighted hit (1/size when the truth is in), the most probable candidate (top-1),
    the Brier score (the squared differences between the probabilities and the truth's
    indicator, summed over the candidates, the truth counted with probability 0 when it is no
    candidate). A case without an effect is a false alarm when its set leaves out calibration
    only. An ``outside`` case counts when called ``unexplained``, when the gap left is
    structured (``complete`` false), or (two effects) when both are in its set. The oracle (the
    true effect fitted with the calibration by someone who knows it) gives the shrinkage beside
    the diagnosis's.
    """
    table = []
    for c, r, g in zip(cases, reports, gaps):
        probs, credible = weighed(r)
        row = {"case": c["case"], "kind": c["kind"], "bench": c["bench"], "truth": c["effect"],
               "values": c["values"], "verdict": r.get("verdict"), "set": credible,
               "probabilities": probs, "selected": r.get("selected"),
               "complete": r.get("complete"), "gap_before": g["before"],
               "gap_oracle": g["oracle"], "gap_ours": g["ours"]}
        if c["kind"] in ("effect", "decoy", "none"):
            truth = c["effect"] if c["kind"] != "none" else CALIBRATION_ONLY
            row["in_set"] = truth in credible
            row["set_size"] = len(credible)
            row["weighted_hit"] = 1 / len(credible) if row["in_set"] else 0.0
            row["top1"] = bool(probs) and max(probs, key=probs.get) == truth
            row["brier"] = sum((p - (name == truth)) ** 2 for name, p in probs.items()) \
                + (0.0 if truth in probs else 1.0)
        if c["kind"] == "none":
            row["false_alarm"] = CALIBRATION_ONLY not in credible
        if c["kind"] in ("effect", "decoy") and g["oracle"] is not None and g["before"]:
            oracle = 1 - g["oracle"] / g["before"]
            ours = 1 - g["ours"] / g["before"]
            row["shrinkage_oracle"], row["shrinkage_ours"] = oracle, ours
            row["shrinkage_vs_oracle"] = ours / oracle if oracle > 0 else None
        if c["kind"] == "outside":
            row["unexplained"] = r.get("verdict") == "unexplained" or (
                r.get("complete") is False and r.get("verdict") not in ("none", "error")
                or bool(c.get("pair")) and set(c["pair"]) <= set(credible))
        table.append(row)

    scores = {**_rates(table), "per_case": table}
    benches = sorted({t["bench"] for t in table})
    if len(benches) > 1:
        scores["by_bench"] = {b: _rates([t for t in table if t["bench"] == b]) for b in benches}
    return scores


def _rates(table):
    """The scores of some rows of the per-case table (None where no case of the kind)."""
    def mean(rows, key):
        values = [float(t[key]) for t in rows if t.get(key) is not None]
        return sum(values) / len(values) if values else None

    keyed = [t for t in table if "in_set" in t]
    effects = [t for t in keyed if t["kind"] in ("effect", "decoy")]
    per_effect = {}
    for t in effects:
        per_effect.setdefault(t["truth"], []).append(t)
    accuracy = {e: {"cases": len(rows), "in_set": mean(rows, "in_set"), "top1": mean(rows, "top1")}
                for e, rows in sorted(per_effect.items())}
    ratios = [t["shrinkage_vs_oracle"] for t in table if t.get("shrinkage_vs_oracle") is not None]
    return {"truth_in_set": mean(keyed, "in_set"), "mean_set_size": mean(keyed, "set_size"),
            "size_weighted_accuracy": mean(keyed, "weighted_hit"), "brier": mean(keyed, "brier"),
            "top1_accuracy": mean(effects, "top1"),
            "false_alarm_rate": mean([t for t in table if t["kind"] == "none"], "false_alarm"),
            "unexplained_rate": mean([t for t in table if t["kind"] == "outside"], "unexplained"),
            "per_effect": accuracy,
            "macro_in_set": (sum(a["in_set"] for a in accuracy.values()) / len(accuracy)
                             if accuracy else None),
            "micro_in_set": mean(effects, "in_set"),
            "reliability": reliability(table),
            "shrinkage_vs_oracle": statistics.median(ratios) if ratios else None,
            "cases": len(table)}


def reliability(table):
    """Predicted probability against observed frequency, per tenth: over every candidate of every
    keyed case, [{"bin", "predicted" (mean), "observed" (share true), "count"}]."""
    pairs = []
    for t in table:
        if "in_set" not in t:
            continue
        truth = t["truth"] if t["kind"] != "none" else CALIBRATION_ONLY
        pairs += [(p, name == truth) for name, p in t["probabilities"].items()]
    out = []
    for b in range(BINS):
        inside = [(p, hit) for p, hit in pairs if b / BINS <= p < (b + 1) / BINS
                  or (b == BINS - 1 and p == 1.0)]
        if inside:
            out.append({"bin": [b / BINS, (b + 1) / BINS], "count": len(inside),
                        "predicted": sum(p for p, _ in inside) / len(inside),
                        "observed": sum(h for _, h in inside) / len(inside)})
    return out
