"""`musclesim benchmark-diagnosis`: the diagnosis checked blind on virtual hardware.

Each case is a measured data set made by running one of the SMA benches with hidden changes:

- ``effect``: one library effect at a random magnitude (SPEC ranges, `MAGNITUDES`);
- ``decoy``: an effect with a look-alike in the library (`DECOYS`: both act at high
  temperatures, or both make the reading trail the model);
- ``none``: no change at all;
- ``outside``: a change the library does not hold (`OUTSIDE`: warmer ambient air, a strain gauge
  with a gain error);

all with nuisances: thermocouple noise and quantisation inside the loop, strain-gauge noise and
quantisation, and an acquisition latency of the strain gauge of 0 or 1 sample behind the
controller's log. A quarter of the effect cases (drawn from a stream of their own) run on the
magnet bench instead, hiding an electromagnet force nonlinearity or a load-cell lag, with laser
and load-cell noise and quantisation (the library's "laser noise" as the nuisance it is: noise
raises the floor, no fit of it can shrink a gap). Cases are written without labels
(data.csv + manifest.toml); the key is hashed into key.sha256 before any diagnosis runs and
written to key.json after. Scores (scores.json): top-1 accuracy over effect and decoy cases,
the median ratio of our held-out shrinkage (the model with every measured signal replayed) to the
oracle's (the true effect at
its true values), the false-alarm rate over ``none`` cases (a verdict naming an effect) and the
``unexplained`` rate over ``outside`` cases.
"""
import hashlib
import json
import math
import statistics
from dataclasses import replace
from pathlib import Path

import numpy as np

from musclesim import dataset, diagnose, master, scenario as scenario_mod
from musclesim.errors import UserError

# the benches: scenario, replayed inputs, observed outputs, the effects that can hide in them
BENCHES = {
    "tracking": ("sma-bench-tracking", ["reference.y"],
                 ["pid.u", "thermocouple.T_meas", "wire.strain"],
                 ["thermocouple lag", "thermocouple bias", "latent heat", "convection change",
                  "training drift"]),
    "stress": ("sma-bench-stress", ["wire.u", "wire.flange.f"],
               ["thermocouple.T_meas", "wire.strain"],
               ["stress dependence ignored", "thermocouple lag", "latent heat"]),
    "magnet": ("sma-bench-magnet", ["wire.u", "magnet.duty"],
               ["loadcell.f_meas", "thermocouple.T_meas", "laser.s_meas"],
               ["electromagnet force nonlinearity", "load-cell lag"]),
}
MAGNET_SHARE = 0.25  # of the effect cases move to the magnet bench (drawn from their own stream)
# Not hidden: clamp heat loss. With the clamps at ambient it is a loss linear in T - T_amb, exactly
# a larger h; the diagnosis rightly calls such data a recalibration of h, not an effect.
# hidden magnitudes: (instance, parameter, low, high), drawn uniformly (SPEC 2.1, 2.6, 5)
MAGNITUDES = {
    "thermocouple lag": [("thermocouple", "tau", 0.1, 0.6)],
    "thermocouple bias": [("thermocouple", "bias", 1.5, 5.0)],  # sign drawn too
    "latent heat": [("wire", "latent_heat", 12e3, 24e3)],
    "clamp heat loss": [("wire", "clamp_conductance", 1e-4, 3e-4)],
    "convection change": [("wire", "h_exponent", 0.06, 0.15)],
    "training drift": [("wire", "drift_amplitude", 0.1, 0.2), ("wire", "drift_shift", 5.0, 10.0)],
    "stress dependence ignored": [("wire", "stress_blend", 0.5, 1.0)],
    "electromagnet force nonlinearity": [("magnet", "nonlinearity", 0.2, 0.5)],
    # a heavily filtered cell: lags of 1-2 samples (20-40 ms) are latency at this data rate
    "load-cell lag": [("loadcell", "tau", 0.1, 0.3)],
}
SIGNED = {"thermocouple bias", "training drift", "electromagnet force nonlinearity"}
# (hidden effect, its decoy in the library): both act at high temperatures, or both make the
# measured temperature trail the wire's model
DECOYS = [("convection change", "clamp heat loss"), ("thermocouple lag", "latent heat"),
          ("latent heat", "thermocouple lag")]
OUTSIDE = {  # K warmer ambient air (the bench's scenario gets an ambient source); strain gain
    "warmer ambient": (6.0, 12.0),
    "strain gauge gain": (0.05, 0.1),  # applied to the recorded strain: gain 1 -+ this
}
# nuisances (the same for every case; magnitudes of a bench like SPEC 2.1's)
TC_NOISE, TC_QUANTUM = 0.08, 0.05  # K
STRAIN_NOISE, STRAIN_QUANTUM = 2e-5, 1e-5
LASER_NOISE, LASER_QUANTUM = 2e-6, 1e-6  # m (the laser-noise effect of the library as nuisance)
LOADCELL_NOISE, LOADCELL_QUANTUM = 2e-3, 1e-3  # N
HELD_OUT_FRACTION = 0.35


def plan(count, seed):
    """The cases' hidden truths: a list of dicts (kind, bench, effect, values, latency, ...)."""
    rng = np.random.default_rng(seed)
    # its own stream, so that moving a case to the magnet bench changes no other case
    magnet_rng = np.random.default_rng([seed, 7])
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
                    rng.integers(0, 2**31)), "strain_gain": 1.0}
        if kind in ("effect", "decoy"):
            pool = BENCHES[bench][3] if kind == "effect" else [d[0] for d in DECOYS]
            effect = pool[rng.integers(len(pool))]
            case["effect"] = effect
            sign = -1.0 if effect in SIGNED and rng.random() < 0.5 else 1.0
            for inst, par, lo, hi in MAGNITUDES[effect]:
                case["values"][f"{inst}.{par}"] = float(sign * rng.uniform(lo, hi))
        if kind == "effect" and magnet_rng.random() < MAGNET_SHARE:
            pool = BENCHES["magnet"][3]
            effect = pool[magnet_rng.integers(len(pool))]
            sign = -1.0 if effect in SIGNED and magnet_rng.random() < 0.5 else 1.0
            case.update(bench="magnet", effect=effect, values={
                f"{inst}.{par}": float(sign * magnet_rng.uniform(lo, hi))
                for inst, par, lo, hi in MAGNITUDES[effect]})
        elif kind == "outside":
            name = list(OUTSIDE)[rng.integers(len(OUTSIDE))]
            case["effect"] = name
            size = float(rng.uniform(*OUTSIDE[name]))
            if name == "warmer ambient":
                case["ambient_K"] = size
            else:
                case["strain_gain"] = float(1 + rng.choice([-1, 1]) * size)
        cases.append(case)
    return cases


def _scenario_path(bench, scenarios_dir):
    return Path(scenarios_dir) / f"{BENCHES[bench][0]}.toml"


def record(case, scenarios_dir, fmu_dir):
    """Run the virtual hardware of `case`: (time, {column: values}) as the bench records them."""
    name, inputs, outputs, _ = BENCHES[case["bench"]]
    sets = [f"{k}={v!r}" for k, v in case["values"].items()]
    sets += [f"thermocouple.noise_std={TC_NOISE!r}", f"thermocouple.quantum={TC_QUANTUM!r}",
             f"thermocouple.seed={case['seed'] % 100000}"]
    if case["bench"] == "magnet":
        sets += [f"laser.noise_std={LASER_NOISE!r}", f"laser.quantum={LASER_QUANTUM!r}",
                 f"laser.seed={case['seed'] % 100001}", f"loadcell.noise_std={LOADCELL_NOISE!r}",
                 f"loadcell.quantum={LOADCELL_QUANTUM!r}", f"loadcell.seed={case['seed'] % 100003}"]
    s = scenario_mod.load(_scenario_path(case["bench"], scenarios_dir), sets)
    s = replace(s, record=tuple(inputs + outputs), metrics={}, plots=())
    if case.get("ambient_K"):  # the air around the wire is warmer than the model's 20 C
        ambient = scenario_mod.Instance("ambient", "SignalSource",
                                        {"offset": 293.15 + case["ambient_K"]})
        s = replace(s, instances={**s.instances, "ambient": ambient},
                    connections=s.connections + (("ambient.y", "wire.T_amb"),))
    res = master.Master(s, fmu_dir).run()
    if res.error:
        raise UserError(f"{case['case']}: the virtual hardware failed: {res.error}")
    rng = np.random.default_rng(case["seed"])
    cols = {c: res[c].copy() for c in inputs + outputs}
    gauge = "wire.strain" if "wire.strain" in cols else "laser.s_meas"
    if gauge == "wire.strain":  # a strain gauge: its noise and quantisation (the laser's in-FMU)
        strain = cols[gauge] * case["strain_gain"] + STRAIN_NOISE * rng.standard_normal(
            len(res.time))
        cols[gauge] = STRAIN_QUANTUM * np.round(strain / STRAIN_QUANTUM)
    lag = case["latency_samples"]
    if lag:  # the gauge's (or laser's) own acquisition lags the controller's log
        cols[gauge] = np.concatenate([np.full(lag, cols[gauge][0]), cols[gauge][:-lag]])
    return res.time, cols


def write_data_set(path, time, cols, inputs, outputs, scenario_ref, description=""):
    """Write a measured data set (data.csv + manifest.toml) blocked in time for held-out."""
    path = Path(path)
    path.mkdir(parents=True, exist_ok=True)
    names = inputs + outputs
    np.savetxt(path / dataset.DATA, np.column_stack([time] + [cols[c] for c in names]),
               delimiter=",", header=",".join(["time", *names]), comments="", fmt="%.9g")
    lines = [f"description = {json.dumps(description)}", f"scenario = {json.dumps(scenario_ref)}",
             f"inputs = {json.dumps(inputs)}", f"outputs = {json.dumps(outputs)}", "",
             "[split]", f"held_out_fraction = {HELD_OUT_FRACTION}", ""]
    (path / dataset.MANIFEST).write_text("\n".join(lines))


def _make(args):
    case, out, scenarios_dir, fmu_dir = args
    time, cols = record(case, scenarios_dir, fmu_dir)
    name, inputs, outputs, _ = BENCHES[case["bench"]]
    ref = str(_scenario_path(case["bench"], scenarios_dir).resolve())
    write_data_set(Path(out) / "cases" / case["case"], time, cols, inputs, outputs, ref,
                   f"blind case {case['case']} on bench {name}")
    return case["case"]


def _diagnose(args):
    case_dir, fmu_dir = args
    try:
        report = diagnose.diagnose(dataset.load(case_dir), fmu_dir)
    except UserError as exc:
        report = {"verdict": "error", "error": str(exc)}
    (Path(case_dir) / "report.json").write_text(json.dumps(report, indent=1, default=float) + "\n")
    return report


def _oracle(args):
    """Held-out gap of the model with every measured signal replayed (the report's section 4):
    nominal and with our selected effects' values, as the report has them, and with the true
    values (the oracle), simulated here."""
    case, case_dir, report, fmu_dir = args
    problem = diagnose.Problem(dataset.load(case_dir), fmu_dir)
    whole = problem.replayed()

    def heldout(values):
        try:
            sims = diagnose.simulate(whole, values, fmu_dir)
        except diagnose.Failed:
            return math.inf
        return diagnose.gap(whole, diagnose.residuals(whole, sims), 1)

    truth = {tuple(k.split(".", 1)): v for k, v in case["values"].items()}
    ours = report.get("shrinkage", {}).get("all")
    before = ours["before"] if ours else heldout({})  # no report section 4: the case failed
    return {"before": before, "oracle": heldout(truth), "ours": ours["after"] if ours else before}


def run(count, seed, out, fmu_dir="fmus", scenarios_dir="scenarios", pmap=None, progress=None):
    """Make `count` cases from `seed` into `out`, diagnose them blind, score; return the scores."""
    pmap = pmap or diagnose._serial
    say = progress or (lambda text: None)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    cases = plan(count, seed)
    say(f"recording {count} cases on the virtual hardware")
    pmap(_make, [(c, out, scenarios_dir, fmu_dir) for c in cases])
    key = json.dumps({"seed": seed, "cases": cases}, indent=1, sort_keys=True) + "\n"
    # sealed: `sha256sum -c key.sha256` checks key.json once it is written, after the diagnosis
    (out / "key.sha256").write_text(hashlib.sha256(key.encode()).hexdigest() + "  key.json\n")
    say("diagnosing blind")
    dirs = [out / "cases" / c["case"] for c in cases]
    reports = pmap(_diagnose, [(d, fmu_dir) for d in dirs])
    (out / "key.json").write_text(key)
    say("scoring against the key and the oracle")
    gaps = pmap(_oracle, [(c, d, r, fmu_dir) for c, d, r in zip(cases, dirs, reports)])
    scores = score(cases, reports, gaps)
    (out / "scores.json").write_text(json.dumps(scores, indent=1) + "\n")
    return scores


def score(cases, reports, gaps):
    """The benchmark's scores and per-case table from the key, the reports and the gaps."""
    table = []
    for c, r, g in zip(cases, reports, gaps):
        row = {"case": c["case"], "kind": c["kind"], "bench": c["bench"], "truth": c["effect"],
               "values": c["values"], "verdict": r.get("verdict"), "selected": r.get("selected"),
               "gap_before": g["before"], "gap_oracle": g["oracle"], "gap_ours": g["ours"]}
        if c["kind"] in ("effect", "decoy"):
            row["correct"] = r.get("verdict") == c["effect"]
            oracle = 1 - g["oracle"] / g["before"]
            ours = 1 - g["ours"] / g["before"]
            row["shrinkage_oracle"], row["shrinkage_ours"] = oracle, ours
            row["shrinkage_vs_oracle"] = ours / oracle if oracle > 0 else None
        elif c["kind"] == "none":
            row["false_alarm"] = r.get("verdict") not in ("none", "unexplained")
        else:
            row["unexplained"] = r.get("verdict") == "unexplained"
        table.append(row)

    def rate(kinds, key):
        rows = [t for t in table if t["kind"] in kinds]
        return sum(bool(t[key]) for t in rows) / len(rows) if rows else None

    ratios = [t["shrinkage_vs_oracle"] for t in table if t.get("shrinkage_vs_oracle") is not None]
    return {"top1_accuracy": rate(("effect", "decoy"), "correct"),
            "shrinkage_vs_oracle": statistics.median(ratios) if ratios else None,
            "false_alarm_rate": rate(("none",), "false_alarm"),
            "unexplained_rate": rate(("outside",), "unexplained"),
            "cases": len(table), "per_case": table}
