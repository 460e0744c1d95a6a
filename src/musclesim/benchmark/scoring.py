"""Scoring the blind benchmark: the own bench's oracle (`oracle`), the verdicts against the key
(`score`: per case and rates, `reliability`), and scores.json (`write_scores`).
"""
from __future__ import annotations

import json
import math
import statistics
from pathlib import Path
from typing import Any

import numpy as np

from musclesim.cosim import ParamRef, replace_file
from musclesim.diagnosis import (CALIBRATION_ONLY, HELD_OUT, OUTSIDE_LIBRARY, TWO_EFFECTS,
                                 Failed, Problem, gap, residuals, simulate_unit)
from musclesim.diagnosis import reliability as diagnosis_reliability

def oracle(args: tuple[dict[str, Any], Any, dict[str, Any], Any]) -> dict[str, float]:
    """Held-out gap of the model with every measured signal replayed (the report's section 4):
    nominal and with our selected effects' values, as the report has them, and with the true
    values (the oracle), simulated here. `args`: (case, its data set, its report.json document,
    the FMU folder), as `musclesim.benchmark.blind.run` maps it."""
    case, ds, report, fmu_dir = args
    problem = Problem(ds, fmu_dir)
    whole = problem.replayed()

    def heldout(values: dict) -> float:
        try:
            sims = simulate_unit(whole, values, fmu_dir)
        except Failed:
            return math.inf
        return gap(whole, residuals(whole, sims), HELD_OUT)

    truth = {ParamRef.parse(k): v for k, v in case["values"].items()}
    ours = report.get("shrinkage", {}).get("all")
    before = ours["before"] if ours else heldout({})  # no report section 4: the case failed
    return {"before": before, "oracle": heldout(truth), "ours": ours["after"] if ours else before}


def write_scores(path: Path, scores: dict[str, Any], bench: str) -> None:
    """Write `scores` into scores.json at `path`: the own bench's (`bench` "own") at the top,
    another bench's under its name ("independent", "family", "crawler-family"); a run replaces
    its own part and keeps the others'."""
    try:
        old = json.loads(path.read_text())
    except (OSError, ValueError):
        old = {}
    others = ("independent", "family", "crawler-family")
    if bench == "own":
        new = {**scores, **{k: old[k] for k in others if k in old}}
    else:
        new = {**{k: v for k, v in old.items() if k != bench}, bench: {"bench": bench, **scores}}
    replace_file(path, json.dumps(new, indent=1) + "\n")


def weighed(report: dict[str, Any]) -> tuple[dict[str, float], list[str]]:
    """{candidate: posterior probability} and the credible set of `report` (a report.json
    document): its evidence (the posterior's credible set, also where a calibrated set of
    causes stands beside it: `musclesim.benchmark.calibrate.score` judges those), or, where the
    diagnosis stopped before weighing (the model matched, or calibration alone did),
    calibration only, certain."""
    ev = report.get("evidence") or {}
    if "candidates" not in ev:
        if report.get("verdict") in ("none", "recalibration"):
            return {CALIBRATION_ONLY: 1.0}, [CALIBRATION_ONLY]
        return {}, []
    return ({c["name"]: c["probability"] for c in ev["candidates"]},
            list(ev.get("credible", ev["set"])))


def score(cases: list[dict[str, Any]], reports: list[dict[str, Any]],
          gaps: list[dict[str, Any]]) -> dict[str, Any]:
    """The benchmark's scores and per-case table from the key (`cases`), the `reports`
    (report.json documents) and the held-out `gaps` (`oracle`'s).

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
    the diagnosis's. Where a report has the calibrated set of causes (a scenario with a shipped
    calibration), ``calibrated`` judges it too (`cause`): whether the truth's cause is in it,
    its size, whether the gate fired.
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
            row["top1"] = bool(probs) and max(probs, key=lambda name: probs[name]) == truth
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
        ev = r.get("evidence") or {}
        if ev.get("calibration"):
            causes = list(ev.get("set", []))
            row["calibrated"] = {"set": causes, "in_set": cause(c) in causes,
                                 "set_size": len(causes),
                                 "gated": bool((ev.get("gate") or {}).get("outside"))}
        table.append(row)

    scores = {**_rates(table), "per_case": table}
    benches = sorted({t["bench"] for t in table})
    if len(benches) > 1:
        scores["by_bench"] = {b: _rates([t for t in table if t["bench"] == b]) for b in benches}
    return scores


def cause(case: dict[str, Any]) -> str:
    """The cause a calibrated set names for `case` of the key: its hidden effect (an effect or
    a decoy posing as one), calibration only (none hidden), two effects (a pair outside the
    library), or outside the library."""
    if case["kind"] == "none":
        return CALIBRATION_ONLY
    if case["kind"] == "outside":
        return TWO_EFFECTS if case.get("pair") else OUTSIDE_LIBRARY
    return str(case["effect"])


def _rates(table: list[dict[str, Any]]) -> dict[str, Any]:
    """The scores of some rows of the per-case table (None where no case of the kind)."""
    def mean(rows: list[dict[str, Any]], key: str) -> float | None:
        values = [float(t[key]) for t in rows if t.get(key) is not None]
        return sum(values) / len(values) if values else None

    keyed = [t for t in table if "in_set" in t]
    effects = [t for t in keyed if t["kind"] in ("effect", "decoy")]
    per_effect: dict[str, list[dict[str, Any]]] = {}
    for t in effects:
        per_effect.setdefault(t["truth"], []).append(t)
    accuracy: dict[str, dict[str, Any]] = {
        e: {"cases": len(rows), "in_set": mean(rows, "in_set"), "top1": mean(rows, "top1")}
        for e, rows in sorted(per_effect.items())}
    ratios = [t["shrinkage_vs_oracle"] for t in table if t.get("shrinkage_vs_oracle") is not None]
    calibrated = [t["calibrated"] for t in table if "calibrated" in t]
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
            "calibrated": {"cases": len(calibrated), "truth_in_set": mean(calibrated, "in_set"),
                           "mean_set_size": mean(calibrated, "set_size"),
                           "gate_rate": mean(calibrated, "gated")} if calibrated else None,
            "cases": len(table)}


def reliability(table: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Predicted probability against observed frequency, per tenth: over every candidate of every
    keyed case of per-case `table`, [{"bin", "predicted" (mean), "observed" (share true),
    "count"}] of the bins that hold any (`musclesim.diagnosis.reliability`'s table)."""
    pairs = []
    for t in table:
        if "in_set" not in t:
            continue
        truth = t["truth"] if t["kind"] != "none" else CALIBRATION_ONLY
        pairs += [(p, name == truth) for name, p in t["probabilities"].items()]
    if not pairs:
        return []
    bins = diagnosis_reliability(np.array([p for p, _ in pairs]), np.array([h for _, h in pairs]))
    return [{"bin": [b["lower"], b["upper"]], "count": b["count"], "predicted": b["stated"],
             "observed": b["observed"]} for b in bins if b["count"]]
